/**
 * @file co_cia402.c
 * @brief CiA 402 device control: controlword decoding, state, statusword.
 */
#include "dtc/canopen/co_cia402.h"

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

co_cia402_action co_cia402_controlword(co_cia402 *c, uint16_t cw)
{
    uint16_t prev = c->controlword;
    c->controlword = cw;
    if (c->state == CO_CIA402_FAULT) {
        if ((cw & CW_FAULT_RESET) != 0u && (prev & CW_FAULT_RESET) == 0u) {
            c->state = CO_CIA402_SWITCH_ON_DISABLED;
            return CO_CIA402_FAULT_RESET;
        }
        return CO_CIA402_KEEP;
    }
    if ((cw & CW_ENABLE_VOLTAGE) == 0u) { /* disable voltage: stop at once and lock out */
        c->state = CO_CIA402_SWITCH_ON_DISABLED;
        return CO_CIA402_STOP;
    }
    if ((cw & CW_QUICK_STOP) == 0u) { /* quick stop */
        if (co_cia402_quick_stop(c) || c->state == CO_CIA402_QUICK_STOP_ACTIVE)
            return CO_CIA402_QUICK_STOP;
        c->state = CO_CIA402_SWITCH_ON_DISABLED;
        return CO_CIA402_STOP;
    }
    if (c->state == CO_CIA402_QUICK_STOP_ACTIVE)
        return CO_CIA402_KEEP; /* only disable voltage interrupts the ramp (options 5..8 not supported) */
    uint16_t cmd = (uint16_t)(cw & (CW_SWITCH_ON | CW_ENABLE_VOLTAGE | CW_QUICK_STOP | CW_ENABLE_OPERATION));
    if ((cmd & 0x7u) == 0x6u) { /* shutdown */
        c->state = CO_CIA402_READY_TO_SWITCH_ON;
        return CO_CIA402_STOP;
    }
    if (cmd == 0x7u) { /* switch on, or disable operation */
        bool was_enabled = c->state == CO_CIA402_OPERATION_ENABLED;
        if (c->state != CO_CIA402_SWITCH_ON_DISABLED)
            c->state = CO_CIA402_SWITCHED_ON;
        return was_enabled ? CO_CIA402_STOP : CO_CIA402_KEEP;
    }
    if (cmd == 0xFu) { /* enable operation (switch on included) */
        if (c->state == CO_CIA402_READY_TO_SWITCH_ON || c->state == CO_CIA402_SWITCHED_ON ||
            c->state == CO_CIA402_OPERATION_ENABLED) {
            c->state = CO_CIA402_OPERATION_ENABLED;
            return CO_CIA402_RUN;
        }
    }
    return CO_CIA402_KEEP;
}

bool co_cia402_quick_stop(co_cia402 *c)
{
    if (c->state != CO_CIA402_OPERATION_ENABLED)
        return false;
    c->state = CO_CIA402_QUICK_STOP_ACTIVE;
    return true;
}

void co_cia402_quick_stop_done(co_cia402 *c)
{
    if (c->state == CO_CIA402_QUICK_STOP_ACTIVE)
        c->state = CO_CIA402_SWITCH_ON_DISABLED;
}

void co_cia402_disable_voltage(co_cia402 *c)
{
    if (c->state != CO_CIA402_FAULT)
        c->state = CO_CIA402_SWITCH_ON_DISABLED;
}

void co_cia402_sync(co_cia402 *c, bool faulted, bool running)
{
    if (faulted)
        c->state = CO_CIA402_FAULT;
    else if (c->state == CO_CIA402_QUICK_STOP_ACTIVE)
        c->state = running ? CO_CIA402_QUICK_STOP_ACTIVE : CO_CIA402_SWITCH_ON_DISABLED;
    else if (c->state == CO_CIA402_FAULT)
        c->state = running ? CO_CIA402_OPERATION_ENABLED : CO_CIA402_SWITCH_ON_DISABLED;
    else if (running)
        c->state = CO_CIA402_OPERATION_ENABLED; /* started by another master (e.g. the SIL) */
    else if (c->state == CO_CIA402_OPERATION_ENABLED)
        c->state = CO_CIA402_SWITCHED_ON;
}

uint16_t co_cia402_statusword(const co_cia402 *c, bool target_reached)
{
    static const uint16_t base[] = {
        [CO_CIA402_SWITCH_ON_DISABLED] = 0x0040u,
        [CO_CIA402_READY_TO_SWITCH_ON] = 0x0021u,
        [CO_CIA402_SWITCHED_ON] = 0x0023u,
        [CO_CIA402_OPERATION_ENABLED] = 0x0027u,
        [CO_CIA402_FAULT] = 0x0008u,
        [CO_CIA402_QUICK_STOP_ACTIVE] = 0x0007u, /* bit 5 (quick stop) low */
    };
    uint8_t st = c->state;
    uint16_t sw = (uint16_t)((st <= CO_CIA402_QUICK_STOP_ACTIVE ? base[st] : 0x0040u) | SW_REMOTE);
    if (st == CO_CIA402_OPERATION_ENABLED && target_reached)
        sw |= SW_TARGET_REACHED;
    return sw;
}
