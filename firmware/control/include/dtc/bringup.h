/**
 * @file bringup.h
 * @brief Bring-up levels: how a new power stage is commissioned step by step
 *        (docs/bringup.md), selected by ctl_cfg.bringup_level (CAN 0x2700:1).
 *
 *  1 gate test: fixed leg patterns, each leg to P and to N and back to O in
 *    turn (BRINGUP_PATTERN_S each); no DC link needed, no DC-link trip;
 *  2 ADC readout: gates off, the samples (and the board's offsets) in telemetry;
 *  3 open-loop V/f: a voltage vector rotating at bringup_hz with the amplitude
 *    omega_e psi_ref, currents in telemetry;
 *  4 the same with the observer judged: its speed against the commanded one;
 *  5 DTC torque control: torque command bringup_te_Nm, no speed loop;
 *  6 sensorless speed control (the drive).
 * Context: ISR (from ctl_step).
 */
#ifndef DTC_BRINGUP_H
#define DTC_BRINGUP_H

#include <stdint.h>

#include "dtc/num.h"
#include "hal/hal_types.h"

#ifdef __cplusplus
extern "C" {
#endif

#define BRINGUP_GATE_TEST 1u
#define BRINGUP_ADC 2u
#define BRINGUP_VF 3u
#define BRINGUP_VF_OBSERVER 4u
#define BRINGUP_TORQUE 5u
#define BRINGUP_SPEED 6u

#define BRINGUP_PATTERN_S R(0.5) /**< time on each gate-test pattern, s */

/**
 * The gate-test pattern at @p t_s since the start: OOO, then each leg in turn
 * to P, back to OOO, to N, back to OOO (never P<->N directly). Context: ISR.
 */
hal_vector bringup_gate_pattern(real_t t_s);

/**
 * V/f: the actuation that applies, on average over the period, the voltage
 * vector of magnitude @p v_mag_V at angle @p theta_rad (stator frame): the
 * inverter state whose voltage projects most onto that direction for duty0,
 * the zero state OOO for the rest. @p vc1_V, @p vc2_V the capacitor voltages.
 * Context: ISR.
 */
hal_actuation bringup_vf(real_t theta_rad, real_t v_mag_V, real_t vc1_V, real_t vc2_V);

#ifdef __cplusplus
}
#endif

#endif /* DTC_BRINGUP_H */
