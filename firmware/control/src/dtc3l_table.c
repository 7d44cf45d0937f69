/**
 * @file dtc3l_table.c
 * @brief Flux sectors and the switching tables of the three-level DTC: the
 *        rules, the tables written out by them (the sector and table look-up
 *        functions are inline in dtc3l.h, they run several times per tick)
 *        and dtc3l_select.
 *
 * The rules (dtc3l_sv_at and dtc3l_demand_offset in dtc3l.h state them; the
 * entries below follow them, and tests/unit/test_dtc3l.cpp checks every entry
 * of dtc3l_table and dtc3l_table6 against the plant's machine equations):
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
#include "dtc/dtc3l_table.h"

/* The two tables by the rules above, written out (dtc3l_table and
 * dtc3l_table6 look them up: the interrupt picks a vector 1..3 times a tick);
 * columns by dtc3l_demand_index: torque up / flux up, up / down,
 * down / up, down / down. tests/unit/test_dtc3l.cpp checks every entry of
 * dtc3l_table and dtc3l_table6 against the machine equations. */
const uint8_t dtc3l_table12_sv[DTC3L_N_SECTORS][4] = {
    {14u, 15u, 18u, 17u}, /* 0 */
    {8u, 9u, 12u, 11u}, /* 1 */
    {15u, 16u, 13u, 18u}, /* 2 */
    {9u, 10u, 7u, 12u}, /* 3 */
    {16u, 17u, 14u, 13u}, /* 4 */
    {10u, 11u, 8u, 7u}, /* 5 */
    {17u, 18u, 15u, 14u}, /* 6 */
    {11u, 12u, 9u, 8u}, /* 7 */
    {18u, 13u, 16u, 15u}, /* 8 */
    {12u, 7u, 10u, 9u}, /* 9 */
    {13u, 14u, 17u, 16u}, /* 10 */
    {7u, 8u, 11u, 10u}, /* 11 */
};

const uint8_t dtc3l_table6_sv[6][4] = {
    {2u, 3u, 6u, 5u}, /* 0 */
    {3u, 4u, 1u, 6u}, /* 1 */
    {4u, 5u, 2u, 1u}, /* 2 */
    {5u, 6u, 3u, 2u}, /* 3 */
    {6u, 1u, 4u, 3u}, /* 4 */
    {1u, 2u, 5u, 4u}, /* 5 */
};

uint8_t dtc3l_select(real_t psi_alpha, real_t psi_beta, int8_t torque, int8_t flux, uint8_t level)
{
    if (level == (uint8_t)DTC3L_LEVEL_LOW && (torque == 1 || torque == -1))
        return dtc3l_table6(dtc3l_sector6(psi_alpha, psi_beta), torque, flux);
    return dtc3l_table(dtc3l_sector(psi_alpha, psi_beta), torque, flux, level);
}
