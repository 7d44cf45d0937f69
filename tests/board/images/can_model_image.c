/* Test image for the twin's FDCAN1 model at the register level (no driver), on the reset
 * clock (HSI16 = 16 MHz, FDCAN kernel clock = PCLK1). One source, one case per build:
 *   CASE 0  internal loop back (CCCR.TEST + MON, TEST.LBCK): filters (classic mask, range,
 *           dual reject, no match, remote frames), Rx FIFO 0/1 elements and acknowledge, Tx FIFO
 *           indices, Tx event FIFO with the message marker, FIFO overflow (blocking: RF0L), the
 *           interrupt line to the NVIC, and the status of a bus without acknowledge. Exits 0
 *           when every check passes, else the number of the failed check.
 *   CASE 1..9  one wrong use each, which the model must stop with a message (exit status 1 of
 *           dtc-board); the image exits 0 only if the model let it through (a test failure).
 * The image is linked with the port's startup (vector table, reset handler), which calls its
 * board_init() and, on an unexpected exception, its board_safe_state(). */
#include <stdint.h>

#include "semihost_min.h"

#ifndef CASE
#define CASE 0
#endif

#define REG(a) (*(volatile uint32_t *)(a))
#define FD(off) REG(0x40006400u + (off))
#define RAM(off) REG(0x4000A400u + (off))
#define RCC_APB1ENR1 REG(0x40021058u)
#define RCC_CCIPR REG(0x40021088u)
#define NVIC_ISER0 REG(0xE000E100u)

#define CCCR 0x018u
#define NBTP 0x01Cu
#define TEST 0x010u
#define PSR 0x044u
#define ECR 0x040u
#define IR 0x050u
#define IE 0x054u
#define ILS 0x058u
#define ILE 0x05Cu
#define RXGFC 0x080u
#define RXF0S 0x090u
#define RXF0A 0x094u
#define RXF1S 0x098u
#define RXF1A 0x09Cu
#define TXBC 0x0C0u
#define TXFQS 0x0C4u
#define TXBRP 0x0C8u
#define TXBAR 0x0CCu
#define TXBTO 0x0D4u
#define TXEFS 0x0E4u
#define TXEFA 0x0E8u

#define FLS 0x000u
#define RF0 0x0B0u
#define RF1 0x188u
#define TEF 0x260u
#define TXB 0x278u
#define ELEM 72u

/* 500 kbit/s from 16 MHz: prescaler 1, 32 tq = sync + 27 + 4, SJW 4: sample point 87.5 % */
#define NBTP_500K ((3u << 25) | (0u << 16) | (26u << 8) | 3u)

/* The reset clock is all this image needs. */
void board_init(void);
void board_init(void) {}

void HardFault_Handler(void);
void HardFault_Handler(void)
{
    sh_puts("can_model_image: HardFault\n");
    sh_exit(90);
}

/* The startup's Default_Handler calls this: an exception nobody expected. */
void board_safe_state(void);
void board_safe_state(void)
{
    sh_puts("can_model_image: unexpected exception (Default_Handler)\n");
    sh_exit(91);
}

static volatile uint32_t g_irq_count;

void FDCAN1_IT0_IRQHandler(void);
void FDCAN1_IT0_IRQHandler(void)
{
    g_irq_count++;
    FD(IR) = 1u; /* RF0N */
}

static void check(int n, int ok, const char *what)
{
    if (ok)
        return;
    sh_puts("can_model_image: check failed: ");
    sh_puts(what);
    sh_puts("\n");
    sh_exit(n);
}

static int wait_reg(uint32_t off, uint32_t mask, uint32_t value)
{
    for (uint32_t n = 0; n < 2000000u; n++)
        if ((FD(off) & mask) == value)
            return 1;
    return 0;
}

static __attribute__((unused)) void clocks(int pclk1)
{
    if (pclk1)
        RCC_CCIPR = (RCC_CCIPR & ~(3u << 24)) | (2u << 24);
    RCC_APB1ENR1 |= 1u << 25;
    (void)RCC_APB1ENR1;
}

/* Configuration from reset (INIT=1): CCE, timing, filters, then leave INIT. */
static __attribute__((unused)) void setup(uint32_t nbtp, int loopback)
{
    clocks(1);
    check(50, wait_reg(CCCR, 1u, 1u), "INIT reads 1 after reset");
    FD(CCCR) |= 2u; /* CCE */
    if (loopback) {
        FD(CCCR) |= (1u << 7) | (1u << 5); /* TEST, MON: internal loop back */
        FD(TEST) = 1u << 4;                /* LBCK */
    }
    FD(NBTP) = nbtp;
    for (uint32_t o = 0; o < 0x350u; o += 4u)
        RAM(o) = 0u;
    RAM(FLS + 0u) = (2u << 30) | (2u << 27) | (0x123u << 16) | 0x7FFu; /* classic mask 0x123 -> FIFO 1 */
    RAM(FLS + 4u) = (0u << 30) | (1u << 27) | (0x100u << 16) | 0x1FFu; /* range 0x100-0x1FF -> FIFO 0 */
    RAM(FLS + 8u) = (1u << 30) | (3u << 27) | (0x055u << 16) | 0x066u; /* dual 0x055/0x066: reject */
    /* 3 standard filters, non-matching standard and extended frames rejected, remote frames rejected */
    FD(RXGFC) = (3u << 16) | (2u << 4) | (2u << 2) | 3u;
    FD(TXBC) = 0u;
    FD(IR) = 0xFFFFFFFFu;
    FD(CCCR) &= ~1u;
    check(51, wait_reg(CCCR, 1u, 0u), "INIT reads 0 after clearing it");
}

static __attribute__((unused)) void put_tx(uint32_t idx, uint32_t id, int rtr, uint32_t dlc, uint32_t w0, uint32_t w1, uint32_t t1extra)
{
    uint32_t e = TXB + idx * ELEM;
    RAM(e + 0u) = (id << 18) | (rtr ? 1u << 29 : 0u);
    RAM(e + 4u) = (dlc << 16) | t1extra;
    RAM(e + 8u) = w0;
    RAM(e + 12u) = w1;
}

/* Send one frame through the Tx FIFO and wait until it is out. */
static __attribute__((unused)) void send(int n, uint32_t id, int rtr, uint32_t dlc, uint32_t w0, uint32_t w1, uint32_t t1extra)
{
    uint32_t fqs = FD(TXFQS);
    check(n, (fqs & (1u << 21)) == 0u, "Tx FIFO not full");
    uint32_t put = (fqs >> 16) & 3u;
    put_tx(put, id, rtr, dlc, w0, w1, t1extra);
    FD(TXBAR) = 1u << put;
    check(n, wait_reg(TXBRP, 1u << put, 0u), "transmission finished (TXBRP cleared)");
    check(n, (FD(TXBTO) >> put) & 1u, "TXBTO set for the element");
}

#if CASE == 0
static void loopback_case(void)
{
    setup(NBTP_500K, 1);
    check(1, wait_reg(PSR, 3u << 3, 1u << 3), "PSR.ACT idle after integration");
    check(2, FD(TXFQS) == 3u, "TXFQS after reset: 3 free, put 0, get 0");

    /* 0x123: classic filter 0 -> Rx FIFO 1, with a Tx event (EFC, message marker 0x5A) */
    send(3, 0x123u, 0, 8u, 0x44332211u, 0x88776655u, (0x5Au << 24) | (1u << 23));
    check(4, FD(TXFQS) == ((1u << 16) | (1u << 8) | 3u), "TXFQS put 1 get 1 free 3 after one frame");
    uint32_t s1 = FD(RXF1S);
    check(5, (s1 & 0xFu) == 1u && ((s1 >> 8) & 3u) == 0u && ((s1 >> 16) & 3u) == 1u, "RXF1S fill 1 get 0 put 1");
    check(6, (RAM(RF1 + 0u) >> 18) == 0x123u, "Rx FIFO 1 element: id 0x123");
    uint32_t r1 = RAM(RF1 + 4u);
    check(7, ((r1 >> 16) & 0xFu) == 8u && ((r1 >> 24) & 0x7Fu) == 0u && !(r1 >> 31), "R1: DLC 8, FIDX 0, ANMF 0");
    check(8, RAM(RF1 + 8u) == 0x44332211u && RAM(RF1 + 12u) == 0x88776655u, "Rx data bytes");
    check(9, (FD(IR) & (1u << 3)) != 0u, "IR.RF1N");
    FD(RXF1A) = 0u;
    check(10, (FD(RXF1S) & 0xFu) == 0u && ((FD(RXF1S) >> 8) & 3u) == 1u, "RXF1A: fill 0, get 1");
    uint32_t efs = FD(TXEFS);
    check(11, (efs & 7u) == 1u, "Tx event FIFO fill 1");
    uint32_t e1 = RAM(TEF + 4u);
    check(12, (e1 >> 24) == 0x5Au && ((e1 >> 22) & 3u) == 1u && ((e1 >> 16) & 0xFu) == 8u, "Tx event: MM, ET=01, DLC");
    check(13, (RAM(TEF + 0u) >> 18) == 0x123u, "Tx event: id");
    FD(TXEFA) = 0u;
    check(14, (FD(TXEFS) & 7u) == 0u, "TXEFA empties the Tx event FIFO");

    /* 0x150: range filter 1 -> Rx FIFO 0 */
    send(15, 0x150u, 0, 2u, 0xBEEFu, 0u, 0u);
    uint32_t s0 = FD(RXF0S);
    check(16, (s0 & 0xFu) == 1u, "RXF0S fill 1");
    check(17, (RAM(RF0 + 0u) >> 18) == 0x150u && ((RAM(RF0 + 4u) >> 24) & 0x7Fu) == 1u, "0x150 stored by filter 1");
    FD(RXF0A) = 0u;

    /* 0x055 (dual filter, reject), 0x300 (no match, ANFS reject), remote 0x150 (RRFS) */
    send(18, 0x055u, 0, 1u, 1u, 0u, 0u);
    send(19, 0x300u, 0, 1u, 1u, 0u, 0u);
    send(20, 0x150u, 1, 0u, 0u, 0u, 0u);
    check(21, (FD(RXF0S) & 0xFu) == 0u && (FD(RXF1S) & 0xFu) == 0u, "rejected frames stored nowhere");

    /* FIFO 0 overflow in blocking mode: the 4th frame is lost, RF0L and RXF0S.RF0L set */
    FD(IR) = 0xFFFFFFFFu;
    for (uint32_t k = 0; k < 4u; k++)
        send(22, 0x100u + k, 0, 1u, k, 0u, 0u);
    s0 = FD(RXF0S);
    check(23, (s0 & 0xFu) == 3u && (s0 & (1u << 24)) && (s0 & (1u << 25)), "RXF0S full, message lost");
    check(24, (FD(IR) & (1u << 2)) != 0u, "IR.RF0L");
    uint32_t get = (s0 >> 8) & 3u;
    check(25, (RAM(RF0 + get * ELEM) >> 18) == 0x100u, "oldest element kept (blocking mode)");
    FD(RXF0A) = (get + 2u) % 3u; /* all three read */
    check(26, (FD(RXF0S) & 0xFu) == 0u, "acknowledging the last of three empties the FIFO");
    FD(IR) = 1u << 2;
    check(27, (FD(RXF0S) & (1u << 25)) == 0u, "RXF0S.RF0L follows IR.RF0L");

    /* three requests at once, in FIFO order from the put index */
    uint32_t put = (FD(TXFQS) >> 16) & 3u;
    for (uint32_t k = 0; k < 3u; k++)
        put_tx((put + k) % 3u, 0x1A0u + k, 0, 1u, k, 0u, 0u);
    FD(TXBAR) = 7u;
    check(28, (FD(TXFQS) & (1u << 21)) != 0u, "TXFQS.TFQF with three pending");
    check(29, wait_reg(TXBRP, 7u, 0u), "three frames sent");
    check(30, (FD(RXF0S) & 0xFu) == 3u && (RAM(RF0 + ((FD(RXF0S) >> 8) & 3u) * ELEM) >> 18) == 0x1A0u,
          "received in FIFO order");
    FD(RXF0A) = ((FD(RXF0S) >> 8) + 2u) % 3u;

    /* interrupt: RF0N on line 0 (ILS.RXFIFO0 = 0), EINT0, NVIC IRQ 21 */
    FD(IR) = 0xFFFFFFFFu;
    FD(IE) = 1u;
    FD(ILS) = 0u;
    FD(ILE) = 1u;
    NVIC_ISER0 = 1u << 21;
    send(31, 0x111u, 0, 0u, 0u, 0u, 0u);
    for (uint32_t n = 0; n < 1000u && g_irq_count == 0u; n++) {
    }
    check(32, g_irq_count == 1u, "FDCAN1_IT0 taken once for RF0N");
    check(33, (FD(ECR) & 0xFFu) == 0u && (FD(PSR) & (7u << 5)) == 0u, "no errors: TEC 0, not EW/EP/BO");

    /* back to configuration: INIT, then CCE once INIT reads 1; NBTP writable again */
    FD(CCCR) |= 1u;
    check(34, wait_reg(CCCR, 1u, 1u), "INIT reads back 1");
    FD(CCCR) |= 2u;
    FD(NBTP) = NBTP_500K;
    check(35, FD(NBTP) == NBTP_500K, "NBTP written in configuration");
    sh_puts("can_model_image: all checks passed\n");
    sh_exit(0);
}
#endif

int main(void)
{
#if CASE == 0
    loopback_case();
#elif CASE == 1 /* protected register without CCE (INIT=1 from reset, CCE=0) */
    clocks(1);
    FD(NBTP) = NBTP_500K;
#elif CASE == 2 /* protected register while running (INIT=0) */
    setup(NBTP_500K, 1);
    FD(RXGFC) = 0u;
#elif CASE == 3 /* Tx request for an element that is not the FIFO's put index */
    setup(NBTP_500K, 1);
    put_tx(1u, 0x123u, 0, 1u, 0u, 0u, 0u);
    FD(TXBAR) = 1u << 1;
#elif CASE == 4 /* Tx request for an element that does not exist */
    setup(NBTP_500K, 1);
    FD(TXBAR) = 1u << 3;
#elif CASE == 5 /* NTSEG2 = 0 is forbidden */
    setup((0u << 25) | (26u << 8) | 0u, 1);
#elif CASE == 6 /* 2 Mbit/s: beyond classic CAN */
    setup((1u << 25) | (4u << 8) | 1u, 1);
#elif CASE == 7 /* CCE right after INIT, before INIT has been accepted */
    setup(NBTP_500K, 1);
    FD(CCCR) = FD(CCCR) | 1u;
    FD(CCCR) = 1u | 2u;
#elif CASE == 8 /* kernel clock HSE (reset selection) while HSE is off */
    clocks(0);
    FD(CCCR) |= 2u;
    FD(NBTP) = NBTP_500K;
    FD(CCCR) &= ~1u;
#elif CASE == 9 /* acknowledge of an Rx FIFO element that is not there */
    setup(NBTP_500K, 1);
    FD(RXF0A) = 0u;
#endif
    sh_puts("can_model_image: the model accepted the wrong use\n");
    sh_exit(0);
}
