/**
 * @file dtc3l_np.h
 * @brief The three-level DTC's choice among a space vector's redundant
 *        switching states: neutral-point balance, fewest commutations, and
 *        never a direct P<->N leg step.
 *
 * A small vector's P-type and N-type states draw opposite neutral-point
 * currents; outside np_band_V the one that drives vc1 - vc2 towards zero is
 * taken (d(vc1 - vc2)/dt = i_np / C), inside the band the one with the fewest
 * leg commutations. No leg ever steps directly between P and N: states that
 * would are excluded, and when the wanted vector has no such state the
 * offending legs are held at O (npc_pn_safe). The zero vector's state (NNN,
 * OOO, PPP) decides which small states stay reachable. Built on the NPC
 * geometry (dtc/npc.h) only.
 */
#ifndef DTC_DTC3L_NP_H
#define DTC_DTC3L_NP_H

#include <stdbool.h>
#include <stdint.h>

#include "dtc/num.h"

#ifdef __cplusplus
extern "C" {
#endif

/**
 * Pick the switching state for space vector @p sv after @p prev_state:
 * never a direct P<->N leg step; for small vectors with |np_dev_V| > np_band_V
 * the state whose neutral-point current drives np_dev_V = vc1 - vc2 towards 0
 * (possibly, when that state is a P<->N step away, as ONN is from PPO, the
 * other state's P<->N-safe one, OON, a different vector, if it balances too);
 * otherwise the fewest leg commutations (NP direction breaks ties). For the
 * zero vector with |np_dev_V| above half the band, the zero state on the way to
 * the balancing state of the small vector @p prev_state belongs to.
 * @param i_abc phase currents during the segment, A
 * Context: ANY.
 */
uint8_t dtc3l_choose_state(uint8_t sv, uint8_t prev_state, real_t np_dev_V, real_t np_band_V,
                           const real_t i_abc[3]);

/** dtc3l_choose_state for @p sv 0..18 and @p prev_state 0..26 (unchecked; the
 *  step's own vectors and states). Context: ANY. */
uint8_t dtc3l_choose_state_unchecked(uint8_t sv, uint8_t prev_state, real_t np_dev_V, real_t np_band_V,
                                     const real_t i_abc[3]);

/** dtc3l_choose_state_unchecked that also reports, for a small vector @p sv
 *  outside the NP band whose first (P-type) state is within reach of
 *  @p prev_state, that state's NP current x @p np_dev_V, A V (*@p push0_VA,
 *  *@p push0_known true; otherwise *@p push0_known false and *@p push0_VA
 *  unspecified). For dtc3l_choose_zero_unchecked after it. Context: ANY. */
uint8_t dtc3l_choose_state_push0_unchecked(uint8_t sv, uint8_t prev_state, real_t np_dev_V, real_t np_band_V,
                                           const real_t i_abc[3], bool *push0_known, real_t *push0_VA);

/** dtc3l_choose_state_unchecked(0, @p prev_state, ...): the zero state after
 *  @p prev_state 0..26. @p push0_known: @p push0_VA is the NP current of the
 *  first state of @p prev_state's vector x @p np_dev_V, A V, already worked
 *  out (dtc3l_choose_state_push0_unchecked when @p prev_state is one of its
 *  vector's states); the NP look-ahead then reuses it instead of working it
 *  out again (the same product: the same choice). Context: ANY. */
uint8_t dtc3l_choose_zero_unchecked(uint8_t prev_state, real_t np_dev_V, real_t np_band_V, const real_t i_abc[3],
                                    bool push0_known, real_t push0_VA);

#ifdef __cplusplus
}
#endif

#endif /* DTC_DTC3L_NP_H */
