/**
 * @file co_cia402.c
 * @brief CiA 402-style device control: controlword, statusword, run/stop.
 */
#include "dtc/canopen/co_cia402.h"

#include "dtc/drive.h"
#include "dtc/num.h"

#define CW_SWITCH_ON 0x0001u
#define CW_ENABLE_VOLTAGE 0x0002u
#define CW_QUICK_STOP 0x0004u /* active low */
#define CW_ENABLE_OPERATION 0x0008u
#define CW_FAULT_RESET 0x0080u

#define SW_REMOTE 0x0200u
#define SW_TARGET_REACHED 0x0400u

void co_cia402_init(co_cia402 *c)
{
    c->state = CO_CIA402_SWITCH_ON_DISABLED;
    c->controlword = 0u;
}

void co_cia402_controlword(struct drive *d, uint16_t cw)
{
    co_cia402 *c = &d->co.cia402;
    uint16_t prev = c->controlword;
    c->controlword = cw;
    if (c->state == CO_CIA402_FAULT) {
        if ((cw & CW_FAULT_RESET) != 0u && (prev & CW_FAULT_RESET) == 0u) {
            drive_set_run(d, false);
            d->clear_faults_req = true; /* the ISR clears what is no longer active */
            c->state = CO_CIA402_SWITCH_ON_DISABLED;
        }
        return;
    }
    if ((cw & CW_ENABLE_VOLTAGE) == 0u || (cw & (CW_QUICK_STOP | CW_ENABLE_VOLTAGE)) == CW_ENABLE_VOLTAGE) {
        /* disable voltage, or quick stop: stop and lock out */
        drive_set_run(d, false);
        c->state = CO_CIA402_SWITCH_ON_DISABLED;
        return;
    }
    uint16_t cmd = (uint16_t)(cw & (CW_SWITCH_ON | CW_ENABLE_VOLTAGE | CW_QUICK_STOP | CW_ENABLE_OPERATION));
    if ((cmd & 0x7u) == 0x6u) { /* shutdown */
        drive_set_run(d, false);
        c->state = CO_CIA402_READY_TO_SWITCH_ON;
    } else if (cmd == 0x7u) { /* switch on, or disable operation */
        if (c->state == CO_CIA402_OPERATION_ENABLED)
            drive_set_run(d, false);
        if (c->state != CO_CIA402_SWITCH_ON_DISABLED)
            c->state = CO_CIA402_SWITCHED_ON;
    } else if (cmd == 0xFu) { /* enable operation (switch on included) */
        if (c->state == CO_CIA402_READY_TO_SWITCH_ON || c->state == CO_CIA402_SWITCHED_ON ||
            c->state == CO_CIA402_OPERATION_ENABLED) {
            drive_set_run(d, true);
            c->state = CO_CIA402_OPERATION_ENABLED;
        }
    }
}

void co_cia402_sync(struct drive *d)
{
    co_cia402 *c = &d->co.cia402;
    bool faulted = d->bg_snap.tel.state == (uint8_t)CTL_FAULTED;
    if (faulted)
        c->state = CO_CIA402_FAULT;
    else if (c->state == CO_CIA402_FAULT)
        c->state = d->run ? CO_CIA402_OPERATION_ENABLED : CO_CIA402_SWITCH_ON_DISABLED;
    else if (d->run)
        c->state = CO_CIA402_OPERATION_ENABLED; /* started by another master (e.g. the SIL) */
    else if (c->state == CO_CIA402_OPERATION_ENABLED)
        c->state = CO_CIA402_SWITCHED_ON;
}

uint16_t co_cia402_statusword(const struct drive *d)
{
    static const uint16_t base[] = {
        [CO_CIA402_SWITCH_ON_DISABLED] = 0x0040u,
        [CO_CIA402_READY_TO_SWITCH_ON] = 0x0021u,
        [CO_CIA402_SWITCHED_ON] = 0x0023u,
        [CO_CIA402_OPERATION_ENABLED] = 0x0027u,
        [CO_CIA402_FAULT] = 0x0008u,
    };
    uint8_t st = d->co.cia402.state;
    uint16_t sw = (uint16_t)((st <= CO_CIA402_FAULT ? base[st] : 0x0040u) | SW_REMOTE);
    if (st == CO_CIA402_OPERATION_ENABLED) {
        /* Target reached: |e_x| below 1 % of the reference or 5 rpm. */
        real_t ref = d->speed_ref_rad_s;
        real_t tol = num_abs(ref) * R(0.01);
        real_t min_tol = R(5.0) * R(0.104719755); /* 5 rpm in rad/s */
        if (tol < min_tol)
            tol = min_tol;
        if (num_abs(ref - d->bg_snap.tel.omega_est_rad_s) <= tol)
            sw |= SW_TARGET_REACHED;
    }
    return sw;
}
