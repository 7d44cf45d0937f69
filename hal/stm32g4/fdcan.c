/**
 * @file fdcan.c
 * @brief FDCAN1 in classic CAN mode (RM0440 44), polled from the background;
 *        its interrupt only wakes the background from its sleep.
 */
#include "fdcan.h"

#include <stdbool.h>
#include <stddef.h>
#include <string.h>

#include "board.h"
#include "chip.h"
#include "clock.h"

#define CAN_BUSOFF_RETRY_MS 100u
#define FDCAN_WAKE_PRIO 15u /* least urgent, as the SysTick: never delays the control tick */

typedef struct {
    bool open;
    bool busoff;
    uint32_t busoff_ms;    /* clock_millis() at the bus-off, then at the last recovery start */
    uint32_t busoff_count;
    uint32_t rx_lost;      /* Rx FIFO 0 overruns seen */
    volatile uint32_t wakeups; /* FDCAN1_IT0 entries: a frame received or the Tx FIFO emptied */
} fdcan_driver;

static fdcan_driver g_fdcan;

/*
 * Nominal bit timing from the FDCAN kernel clock (PCLK1 = SYSCLK): the
 * prescaler and number of time quanta (8..80) whose sample point is closest
 * to 87.5 % (CiA 301 recommendation), SJW = phase segment 2 (RM0440, FDCAN chapter, FDCAN_NBTP description).
 */
static bool can_bit_timing(uint32_t clk_hz, uint32_t bitrate, uint32_t *nbtp)
{
    uint32_t best_err = 1000u, best = 0u;
    for (uint32_t brp = 1u; brp <= 32u; brp++) {
        if (clk_hz % (brp * bitrate) != 0u)
            continue;
        uint32_t ntq = clk_hz / (brp * bitrate);
        if (ntq < 8u || ntq > 80u)
            continue;
        uint32_t sp_tq = (ntq * 875u + 500u) / 1000u; /* sync + tseg1 */
        uint32_t tseg1 = sp_tq - 1u;
        uint32_t tseg2 = ntq - sp_tq;
        if (tseg2 < 2u || tseg1 > 256u || tseg2 > 128u)
            continue;
        uint32_t sp = sp_tq * 1000u / ntq;
        uint32_t err = sp > 875u ? sp - 875u : 875u - sp;
        if (err < best_err) {
            best_err = err;
            best = ((tseg2 - 1u) << FDCAN_NBTP_NSJW_SHIFT) | ((brp - 1u) << FDCAN_NBTP_NBRP_SHIFT) |
                   ((tseg1 - 1u) << FDCAN_NBTP_NTSEG1_SHIFT) | ((tseg2 - 1u) << FDCAN_NBTP_NTSEG2_SHIFT);
        }
    }
    *nbtp = best;
    return best_err < 1000u;
}

/* Standard filter element (RM0440, FDCAN chapter, "Standard message ID filter element"):
 * SFT range (0) or dual (1), SFEC 1 = store in Rx FIFO 0. */
static uint32_t can_filter(uint32_t type, uint32_t id1, uint32_t id2)
{
    return (type << 30) | (1u << 27) | (id1 << 16) | id2;
}

int fdcan_open(uint32_t bitrate_bps)
{
    if (bitrate_bps != 125000u && bitrate_bps != 250000u && bitrate_bps != 500000u &&
        bitrate_bps != 1000000u)
        return HAL_EINVAL;
    uint32_t nbtp;
    if (!can_bit_timing(clock_sysclk_hz(), bitrate_bps, &nbtp))
        return HAL_EIO;

    RCC_CCIPR = (RCC_CCIPR & ~RCC_CCIPR_FDCANSEL_MASK) | RCC_CCIPR_FDCANSEL_PCLK1;
    RCC_APB1ENR1 |= RCC_APB1ENR1_FDCANEN;
    (void)RCC_APB1ENR1;

    /* Initialisation mode, then configuration change enable (RM0440, FDCAN chapter, FDCAN_CCCR description). */
    FDCAN1_CCCR |= FDCAN_CCCR_INIT;
    if (!chip_wait(&FDCAN1_CCCR, FDCAN_CCCR_INIT, FDCAN_CCCR_INIT, CHIP_WAIT_LOOPS))
        return HAL_EIO;
    FDCAN1_CCCR |= FDCAN_CCCR_CCE;
    /* Classic CAN: no FD operation, no bit-rate switching; automatic
     * retransmission on (DAR = 0). */
    FDCAN1_CCCR &= ~(FDCAN_CCCR_FDOE | FDCAN_CCCR_BRSE | FDCAN_CCCR_DAR);
    FDCAN1_NBTP = nbtp;

    /* Message RAM: clear it, then the filters of this node's function codes
     * (the node id is the firmware's, so the exact match is in software). */
    for (uint32_t ofs = 0u; ofs < SRAMCAN_SIZE; ofs += 4u)
        SRAMCAN_WORD(ofs) = 0u;
    SRAMCAN_WORD(SRAMCAN_FLSSA + 0u) = can_filter(1u, 0x000u, 0x080u); /* NMT, SYNC */
    SRAMCAN_WORD(SRAMCAN_FLSSA + 4u) = can_filter(0u, 0x200u, 0x57Fu); /* RPDO1..4 */
    SRAMCAN_WORD(SRAMCAN_FLSSA + 8u) = can_filter(0u, 0x600u, 0x67Fu); /* SDO requests */
    SRAMCAN_WORD(SRAMCAN_FLSSA + 12u) = can_filter(0u, 0x700u, 0x77Fu); /* heartbeats, node guarding */
    /* 4 standard filters; everything else and every extended or remote
     * extended frame is rejected. */
    FDCAN1_RXGFC = (4u << FDCAN_RXGFC_LSS_SHIFT) | FDCAN_RXGFC_ANFS_REJECT | FDCAN_RXGFC_ANFE_REJECT |
                   FDCAN_RXGFC_RRFE;
    FDCAN1_TXBC = 0u; /* TFQM = 0: Tx FIFO (3 elements, fixed) */
    /* Polled from the background; the interrupt (least urgent, below the
     * tick) only wakes the background when a frame came in or the Tx FIFO
     * emptied (board_idle). */
    FDCAN1_IE = FDCAN_IE_RF0NE | FDCAN_IE_TFEE; /* both in line 0 (ILS = 0) */
    FDCAN1_ILE = FDCAN_ILE_EINT0;
    FDCAN1_IR = 0xFFFFFFFFu;

    chip_nvic_enable(IRQN_FDCAN1_IT0, FDCAN_WAKE_PRIO);
    FDCAN1_CCCR &= ~FDCAN_CCCR_INIT; /* joins after 11 recessive bits */
    g_fdcan.open = true;
    g_fdcan.busoff = false;
    return HAL_OK;
}

/** FDCAN1 interrupt line 0: a frame in Rx FIFO 0 or the Tx FIFO emptied. The
 * flags are cleared and the wake-up counted; the background does the work.
 * Context: interrupt, FDCAN_WAKE_PRIO. */
void FDCAN1_IT0_IRQHandler(void)
{
    FDCAN1_IR = FDCAN_IR_RF0N | FDCAN_IR_TFE; /* rc_w1 */
    g_fdcan.wakeups++;
}

uint32_t fdcan_wakeups(void) { return g_fdcan.wakeups; }

/* Bus-off: the controller sets INIT by itself; after CAN_BUSOFF_RETRY_MS
 * clearing INIT starts the recovery (128 x 11 recessive bits; RM0440, FDCAN chapter, bus-off recovery).
 * @return true while the controller is usable. Context: BG. */
static bool can_service(void)
{
    if (!g_fdcan.open)
        return false;
    /* PSR.BO stays set from bus-off until the recovery sequence completes. */
    if ((FDCAN1_PSR & FDCAN_PSR_BO) != 0u) {
        if (!g_fdcan.busoff) {
            g_fdcan.busoff = true;
            g_fdcan.busoff_ms = clock_millis();
            g_fdcan.busoff_count++;
            board_fault_record(BOARD_FAULT_CAN_BUSOFF);
        } else if ((FDCAN1_CCCR & FDCAN_CCCR_INIT) != 0u &&
                   clock_millis() - g_fdcan.busoff_ms >= CAN_BUSOFF_RETRY_MS) {
            FDCAN1_CCCR &= ~FDCAN_CCCR_INIT; /* start the recovery */
            g_fdcan.busoff_ms = clock_millis();
        }
        return false;
    }
    g_fdcan.busoff = false;
    return true;
}

/* PSR.BO (RM0440, FDCAN_PSR) is read through can_service, which also starts
 * the recovery, so a caller that only polls the state still recovers. */
void fdcan_get_state(hal_can_state *out)
{
    (void)can_service();
    out->bus_off = g_fdcan.open && g_fdcan.busoff;
    out->bus_off_count = g_fdcan.busoff_count;
}

int fdcan_send(const hal_can_frame *frame)
{
    if (frame == NULL || frame->id > 0x7FFu || frame->dlc > 8u)
        return HAL_EINVAL;
    if (!can_service())
        return HAL_EIO;
    uint32_t fqs = FDCAN1_TXFQS;
    if ((fqs & FDCAN_TXFQS_TFQF) != 0u)
        return HAL_EBUSY; /* never waits: the caller retries later */
    uint32_t idx = (fqs & FDCAN_TXFQS_TFQPI_MASK) >> FDCAN_TXFQS_TFQPI_SHIFT;
    uint32_t e = SRAMCAN_TBSA + idx * SRAMCAN_ELEM_SIZE;
    uint8_t d[8] = {0};
    memcpy(d, frame->data, frame->dlc);
    /* T0: RTR [29], standard id [28:18]; T1: DLC [19:16] (classic, no EFC). */
    SRAMCAN_WORD(e + 0u) = ((uint32_t)frame->id << 18) | (frame->rtr ? (1u << 29) : 0u);
    SRAMCAN_WORD(e + 4u) = (uint32_t)frame->dlc << 16;
    SRAMCAN_WORD(e + 8u) = (uint32_t)d[0] | ((uint32_t)d[1] << 8) | ((uint32_t)d[2] << 16) | ((uint32_t)d[3] << 24);
    SRAMCAN_WORD(e + 12u) = (uint32_t)d[4] | ((uint32_t)d[5] << 8) | ((uint32_t)d[6] << 16) | ((uint32_t)d[7] << 24);
    FDCAN1_TXBAR = 1u << idx;
    return HAL_OK;
}

int fdcan_recv(hal_can_frame *frame)
{
    if (frame == NULL)
        return HAL_EINVAL;
    (void)can_service();
    if (!g_fdcan.open)
        return HAL_EAGAIN;
    if ((FDCAN1_IR & FDCAN_IR_RF0L) != 0u) {
        FDCAN1_IR = FDCAN_IR_RF0L;
        g_fdcan.rx_lost++;
    }
    for (;;) {
        uint32_t s = FDCAN1_RXF0S;
        if ((s & FDCAN_RXF0S_F0FL_MASK) == 0u)
            return HAL_EAGAIN;
        uint32_t idx = (s & FDCAN_RXF0S_F0GI_MASK) >> FDCAN_RXF0S_F0GI_SHIFT;
        uint32_t e = SRAMCAN_RF0SA + idx * SRAMCAN_ELEM_SIZE;
        uint32_t r0 = SRAMCAN_WORD(e + 0u);
        uint32_t r1 = SRAMCAN_WORD(e + 4u);
        uint32_t w[2] = {SRAMCAN_WORD(e + 8u), SRAMCAN_WORD(e + 12u)};
        FDCAN1_RXF0A = idx;
        if ((r0 & (1u << 30)) != 0u || (r1 & (1u << 21)) != 0u)
            continue; /* extended or FD frame: not ours (filters reject them anyway) */
        uint32_t dlc = (r1 >> 16) & 0xFu;
        frame->id = (uint16_t)((r0 >> 18) & 0x7FFu);
        frame->rtr = (r0 & (1u << 29)) != 0u;
        frame->dlc = (uint8_t)(dlc > 8u ? 8u : dlc);
        for (unsigned k = 0u; k < 8u; k++)
            frame->data[k] = (uint8_t)(w[k / 4u] >> (8u * (k % 4u)));
        return HAL_OK;
    }
}
