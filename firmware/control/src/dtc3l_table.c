/**
 * @file dtc3l_table.c
 * @brief Flux sectors and the switching tables of the three-level DTC: the
 *        rules (the sector and table functions themselves are inline in
 *        dtc3l.h, they run several times per tick) and dtc3l_select.
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

uint8_t dtc3l_select(real_t psi_alpha, real_t psi_beta, int8_t torque, int8_t flux, uint8_t level)
{
    if (level == (uint8_t)DTC3L_LEVEL_LOW && (torque == 1 || torque == -1))
        return dtc3l_table6(dtc3l_sector6(psi_alpha, psi_beta), torque, flux);
    return dtc3l_table(dtc3l_sector(psi_alpha, psi_beta), torque, flux, level);
}
