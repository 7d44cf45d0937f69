/**
 * @file dtc3l_table.c
 * @brief Flux sectors and the switching tables of the three-level DTC.
 *
 * The tables are written as their geometric rules rather than as literal
 * entries (tests/unit/test_dtc3l.cpp checks every entry against the plant's
 * machine equations):
 *  - 12-sector table (HIGH level, strong demands): the vector at the sector
 *    centre +60 deg (torque up, flux up), +120 deg (up, down), -60 / -120 deg
 *    (torque down); 45..75 deg (105..135 deg) from the flux over the whole
 *    30 deg sector. Large vectors lie there in even sectors, medium ones in odd.
 *  - 6-sector small-vector table (LOW level): the same offsets from the small
 *    vector nearest to the flux (sectors of 60 deg centred on the small
 *    vectors), i.e. the classic two-level table on the inner hexagon. Every
 *    transition between these vectors and the adjacent zero state costs one
 *    leg commutation, and all of them can balance the neutral point; the
 *    medium vectors, which cost two commutations against a zero state and draw
 *    an uncontrolled NP current, are left to the strong demands.
 */
#include "dtc/dtc3l.h"

/* tan(15), tan(30), tan(75) deg: sector boundaries inside a quadrant */
#define TAN15 R(0.267949192)
#define TAN30 R(0.577350269)
#define TAN75 R(3.732050808)

uint8_t dtc3l_sector(real_t psi_alpha, real_t psi_beta)
{
    real_t ax = num_abs(psi_alpha), ay = num_abs(psi_beta);
    /* q: 30 deg step nearest to the angle folded into the first quadrant */
    unsigned q;
    if (ay < num_mul(TAN15, ax))
        q = 0u;
    else if (ay < ax)
        q = 1u;
    else if (ay < num_mul(TAN75, ax))
        q = 2u;
    else
        q = 3u;
    if (psi_alpha >= R(0.0))
        return (uint8_t)(psi_beta >= R(0.0) ? q : (12u - q) % 12u);
    return (uint8_t)(psi_beta >= R(0.0) ? 6u - q : 6u + q);
}

uint8_t dtc3l_sector6(real_t psi_alpha, real_t psi_beta)
{
    /* within a quadrant the only boundary is at 30 deg from the alpha axis */
    bool near_axis = num_abs(psi_beta) < num_mul(TAN30, num_abs(psi_alpha));
    if (psi_alpha >= R(0.0))
        return (uint8_t)(near_axis ? 0u : (psi_beta >= R(0.0) ? 1u : 5u));
    return (uint8_t)(near_axis ? 3u : (psi_beta >= R(0.0) ? 2u : 4u));
}

/* Space vector at direction @p dir (0..11, 30 deg steps); even directions hold small or large vectors. */
static uint8_t sv_at(unsigned dir, bool large)
{
    dir %= 12u;
    if (dir & 1u)
        return (uint8_t)(7u + (dir - 1u) / 2u);
    return (uint8_t)((large ? 13u : 1u) + dir / 2u);
}

/* Offset from the reference direction, in 30 deg steps mod 12. */
static unsigned demand_offset(int8_t torque, int8_t flux)
{
    if (torque > 0)
        return flux > 0 ? 2u : 4u;
    return flux > 0 ? 10u : 8u;
}

uint8_t dtc3l_table(uint8_t sector, int8_t torque, int8_t flux, uint8_t level)
{
    if (torque == 0)
        return 0u;
    (void)level; /* the HIGH level and the strong demands share this table */
    return sv_at((unsigned)(sector % 12u) + demand_offset(torque, flux), true);
}

uint8_t dtc3l_table6(uint8_t sector6, int8_t torque, int8_t flux)
{
    if (torque == 0)
        return 0u;
    return sv_at(2u * (unsigned)(sector6 % 6u) + demand_offset(torque, flux), false);
}

uint8_t dtc3l_table_flux_hold(uint8_t sector6) { return sv_at(2u * (unsigned)(sector6 % 6u), false); }

uint8_t dtc3l_select(real_t psi_alpha, real_t psi_beta, int8_t torque, int8_t flux, uint8_t level)
{
    if (level == (uint8_t)DTC3L_LEVEL_LOW && (torque == 1 || torque == -1))
        return dtc3l_table6(dtc3l_sector6(psi_alpha, psi_beta), torque, flux);
    return dtc3l_table(dtc3l_sector(psi_alpha, psi_beta), torque, flux, level);
}
