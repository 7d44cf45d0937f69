/**
 * @file dtc3l_table.h
 * @brief The switching tables of the three-level DTC: flux sectors, the
 *        12-sector table of the large and medium vectors, the 6-sector table
 *        of the small vectors, and the flux-holding small vector.
 *
 * Vocabulary (space vectors as in dtc/npc.h)
 *  - direction: 0..11, the angle of a non-zero sv in steps of 30 deg; even
 *    directions hold small and large vectors, odd directions medium ones.
 *  - sector: 0..11, the stator-flux angle in 30 deg sectors centred on
 *    direction s (sector s spans s*30 - 15 .. s*30 + 15 deg); sector6: 0..5,
 *    60 deg sectors centred on the small vectors (s6*60 - 30 .. s6*60 + 30).
 *
 * The rules of the tables are explained in dtc3l_table.c and in dtc/dtc3l.h
 * (selection rule). The sectors and look-ups are small and run several times
 * per tick: inline. Every function is pure; Context: ANY.
 */
#ifndef DTC_DTC3L_TABLE_H
#define DTC_DTC3L_TABLE_H

#include <stdbool.h>
#include <stdint.h>

#include "dtc/num.h"

#ifdef __cplusplus
extern "C" {
#endif

#define DTC3L_N_SECTORS 12u /**< flux sectors of 30 deg */

/** Voltage level chosen from the speed: which table the DTC reads. */
typedef enum {
    DTC3L_LEVEL_LOW = 0,  /**< small vectors, 6 sectors */
    DTC3L_LEVEL_HIGH = 1, /**< large and medium vectors, 12 sectors */
} dtc3l_level;

/* tan(15), tan(30), tan(75) deg: sector boundaries inside a quadrant */
#define DTC3L_TAN15 R(0.267949192)
#define DTC3L_TAN30 R(0.577350269)
#define DTC3L_TAN75 R(3.732050808)

/** Sector 0..11 of the flux (psi_alpha, psi_beta): 30 deg sectors centred on
 *  30 deg * sector. No trigonometry. Context: ANY. */
static inline uint8_t dtc3l_sector(real_t psi_alpha, real_t psi_beta)
{
    real_t ax = num_abs(psi_alpha), ay = num_abs(psi_beta);
    /* q: 30 deg step nearest to the angle folded into the first quadrant */
    unsigned q;
    if (ay < num_mul(DTC3L_TAN15, ax))
        q = 0u;
    else if (ay < ax)
        q = 1u;
    else if (ay < num_mul(DTC3L_TAN75, ax))
        q = 2u;
    else
        q = 3u;
    if (psi_alpha >= R(0.0))
        return (uint8_t)(psi_beta >= R(0.0) ? q : (12u - q) % 12u);
    return (uint8_t)(psi_beta >= R(0.0) ? 6u - q : 6u + q);
}

/** Sector 0..5 of the flux: 60 deg sectors centred on the small vectors,
 *  60 deg * sector. No trigonometry. Context: ANY. */
static inline uint8_t dtc3l_sector6(real_t psi_alpha, real_t psi_beta)
{
    /* within a quadrant the only boundary is at 30 deg from the alpha axis */
    bool near_axis = num_abs(psi_beta) < num_mul(DTC3L_TAN30, num_abs(psi_alpha));
    if (psi_alpha >= R(0.0))
        return (uint8_t)(near_axis ? 0u : (psi_beta >= R(0.0) ? 1u : 5u));
    return (uint8_t)(near_axis ? 3u : (psi_beta >= R(0.0) ? 2u : 4u));
}

/** dtc3l_sector (@p sector) and dtc3l_sector6 (@p sector6) of the same flux
 *  with one set of compares: the 60 deg sectors' boundary at 30 deg from the
 *  alpha axis lies inside 12-sector 1 of the quadrant, so it is the one more
 *  compare there (below 15 deg it is near the axis, from 45 deg on it is not;
 *  the products by tan15 < tan30 < 1 keep that order in floats). Context: ANY. */
static inline void dtc3l_sectors(real_t psi_alpha, real_t psi_beta, uint8_t *sector, uint8_t *sector6)
{
    real_t ax = num_abs(psi_alpha), ay = num_abs(psi_beta);
    unsigned q;
    bool near_axis;
    if (ay < num_mul(DTC3L_TAN15, ax)) {
        q = 0u;
        near_axis = true;
    } else if (ay < ax) {
        q = 1u;
        near_axis = ay < num_mul(DTC3L_TAN30, ax);
    } else {
        q = ay < num_mul(DTC3L_TAN75, ax) ? 2u : 3u;
        near_axis = false;
    }
    if (psi_alpha >= R(0.0)) {
        *sector = (uint8_t)(psi_beta >= R(0.0) ? q : (12u - q) % 12u);
        *sector6 = (uint8_t)(near_axis ? 0u : (psi_beta >= R(0.0) ? 1u : 5u));
    } else {
        *sector = (uint8_t)(psi_beta >= R(0.0) ? 6u - q : 6u + q);
        *sector6 = (uint8_t)(near_axis ? 3u : (psi_beta >= R(0.0) ? 2u : 4u));
    }
}

/** Space vector at direction @p dir (0..11 after mod 12, 30 deg steps); even
 *  directions hold small (@p large false) or large vectors. Context: ANY. */
static inline uint8_t dtc3l_sv_at(unsigned dir, bool large)
{
    dir %= 12u;
    if (dir & 1u)
        return (uint8_t)(7u + (dir - 1u) / 2u);
    return (uint8_t)((large ? 13u : 1u) + dir / 2u);
}

/** Offset of the demanded vector from the reference direction, in 30 deg
 *  steps mod 12 (+60 / +120 deg up, -60 / -120 deg down). Context: ANY. */
static inline unsigned dtc3l_demand_offset(int8_t torque, int8_t flux)
{
    if (torque > 0)
        return flux > 0 ? 2u : 4u;
    return flux > 0 ? 10u : 8u;
}

/** Column of the written-out tables for @p torque (> 0 up, else down) and
 *  @p flux (> 0 raise, else lower): the order of dtc3l_demand_offset's four
 *  cases (+60, +120, -60, -120 deg). Context: ANY. */
static inline unsigned dtc3l_demand_index(int8_t torque, int8_t flux)
{
    return (torque > 0 ? 0u : 2u) + (flux > 0 ? 0u : 1u);
}

/** dtc3l_sv_at(sector + dtc3l_demand_offset(...), true) by sector 0..11 and
 *  dtc3l_demand_index (dtc3l_table.c). */
extern const uint8_t dtc3l_table12_sv[DTC3L_N_SECTORS][4];
/** dtc3l_sv_at(2 sector6 + dtc3l_demand_offset(...), false) by sector6 0..5 and
 *  dtc3l_demand_index (dtc3l_table.c). */
extern const uint8_t dtc3l_table6_sv[6][4];

/**
 * The 12-sector table of the large and medium vectors: space vector for
 * @p sector (0..11), torque demand @p torque (-2..2; 0 = hold: the zero
 * vector), flux demand @p flux (+1 raise, -1 lower). @p level is accepted for
 * symmetry with dtc3l_select and does not change the result. Context: ANY.
 */
static inline uint8_t dtc3l_table(uint8_t sector, int8_t torque, int8_t flux, uint8_t level)
{
    if (torque == 0)
        return 0u;
    (void)level; /* the HIGH level and the strong demands share this table */
    return dtc3l_table12_sv[sector % 12u][dtc3l_demand_index(torque, flux)];
}

/** The 6-sector table of the small vectors (LOW level): space vector for
 *  @p sector6 (0..5), @p torque (sign only; 0 = zero vector), @p flux. Context: ANY. */
static inline uint8_t dtc3l_table6(uint8_t sector6, int8_t torque, int8_t flux)
{
    if (torque == 0)
        return 0u;
    return dtc3l_table6_sv[sector6 % 6u][dtc3l_demand_index(torque, flux)];
}

/** Flux-holding small vector: the small vector nearest to the flux, whose
 *  tangential part is at most half of it. Context: ANY. */
static inline uint8_t dtc3l_table_flux_hold(uint8_t sector6)
{
    return (uint8_t)(1u + sector6 % 6u); /* dtc3l_sv_at(2 (sector6 mod 6), false) */
}

/**
 * The switching table as the DTC uses it: the 6-sector small-vector table for
 * the LOW level and demands +-1, the 12-sector table otherwise.
 * @return space vector 0..18. Context: ANY.
 */
uint8_t dtc3l_select(real_t psi_alpha, real_t psi_beta, int8_t torque, int8_t flux, uint8_t level);

#ifdef __cplusplus
}
#endif

#endif /* DTC_DTC3L_TABLE_H */
