/**
 * @file hal_host.h
 * @brief Host binding of the HAL: a simulated board the SIL engine drives.
 *
 * The engine owns a hal_host_board, binds it with hal_host_bind(), and for
 * every control period: fills the sample (hal_host_set_sample), runs the tick
 * handler as the interrupt would (hal_host_run_tick), then reads the latched
 * actuation (hal_host_take_actuation) and integrates the plant over the period.
 * CAN frames go to a pluggable backend (in-memory loopback for tests, a
 * SocketCAN raw socket for `dtc-sim --can IFACE`). The NVM is a byte array,
 * optionally mirrored to a file.
 *
 * Time: hal_cycles() counts real host time, free-running and wrapping at
 * 2^32 counts, at hal_cycles_hz() counts per second. On x86-64 it is the
 * time-stamp counter (no system call), its rate measured once against
 * CLOCK_MONOTONIC (about 10 ms, in hal_host_bind or the first call), so
 * hal_cycles_hz() is the host's TSC rate, e.g. 2.5e9 (shifted down if it would
 * not fit 32 bits); elsewhere it is CLOCK_MONOTONIC in ns (hal_cycles_hz() =
 * 1e9). hal_millis() follows the board's simulated time b->t_s.
 */
#ifndef HAL_HOST_HAL_HOST_H
#define HAL_HOST_HAL_HOST_H

#include <stdbool.h>
#include <stdint.h>
#include <time.h>

#include "hal/hal.h"

#ifdef __cplusplus
extern "C" {
#endif

/** A CAN backend: non-blocking send and receive, HAL return codes. */
typedef struct {
    void *ctx;
    int (*send)(void *ctx, const hal_can_frame *f);
    int (*recv)(void *ctx, hal_can_frame *f);
    /**
     * Optional (NULL: the backend cannot wait; sleep instead). Block for at
     * most @p timeout (relative; NULL: no limit) until a received frame is
     * waiting. The realtime engine sleeps through this between its pacing
     * deadlines, so an idle bus costs no system call per tick: once wait_rx
     * has been called, recv() makes a system call only after wait_rx saw a
     * frame, until it finds the queue empty again (a frame that arrives
     * between two waits is read after the next wait_rx).
     * @return 1 a frame is waiting (recv() will read it), 0 the timeout
     *         passed, HAL_EAGAIN a signal interrupted the wait, HAL_EIO on failure.
     */
    int (*wait_rx)(void *ctx, const struct timespec *timeout);
    /**
     * Optional (NULL: never bus-off). The controller's bus condition as
     * hal_can_get_state reports it (SocketCAN: from CAN_ERR_BUSOFF and
     * CAN_ERR_RESTARTED error frames; loopback: injected by a test).
     */
    void (*state)(void *ctx, hal_can_state *out);
} hal_host_can_backend;

#define HAL_HOST_NVM_SIZE 4096u

typedef struct {
    /* control tick */
    hal_tick_handler handler;
    void *handler_ctx;
    uint32_t period_us;
    bool tick_running;

    /* sample and actuation */
    hal_sample sample;
    bool sample_pending;          /**< set by the engine, cleared by the first read */
    hal_actuation act_latched;    /**< what the firmware latched for the next period */
    bool act_written;             /**< the firmware called hal_actuate this tick */

    /* gates and faults */
    bool gates_enabled;
    bool fault_input;
    bool tick_missed;             /**< set by the engine to inject a missed deadline; hal_tick_missed reads and clears it */

    /* time: simulated seconds (advanced by the engine) */
    double t_s;

    /* CAN */
    hal_host_can_backend can;     /**< no backend (send/recv NULL): frames are dropped */
    bool can_open;
    uint32_t can_bitrate;

    /* non-volatile memory */
    uint8_t nvm[HAL_HOST_NVM_SIZE];
    const char *nvm_path;         /**< mirror file (NULL: memory only) */
    long nvm_write_budget;        /**< bytes that may still be written before a simulated power loss (-1: unlimited) */

    /* watchdog */
    uint32_t wdg_timeout_ms;
    double wdg_last_kick_s;
} hal_host_board;

/** Reset @p b to a powered-down board (gates off, erased NVM = 0xFF, no CAN backend). */
void hal_host_board_init(hal_host_board *b);

/** Make @p b the board the HAL functions act on (one per process at a time). */
void hal_host_bind(hal_host_board *b);

/** The bound board, or NULL. */
hal_host_board *hal_host_bound(void);

/** Engine: provide this period's sample (what the ADC converted at the period start). */
void hal_host_set_sample(hal_host_board *b, const hal_sample *s);

/** Engine: run the tick handler once, as the interrupt would. No-op unless the tick is started. */
void hal_host_run_tick(hal_host_board *b);

/** Engine: the actuation to apply during the next period (all legs O when the gates are off). */
void hal_host_take_actuation(const hal_host_board *b, hal_actuation *act, bool *gates_on);

/**
 * Load the NVM mirror file into memory (missing file: erased NVM). A file
 * that is not exactly HAL_HOST_NVM_SIZE bytes, or cannot be read, is left
 * untouched and the in-memory NVM is not changed.
 * Does not set b->nvm_path (the caller decides whether writes are mirrored).
 * @return HAL_OK or HAL_EIO.
 */
int hal_host_nvm_load(hal_host_board *b, const char *path);

/**
 * @return true when the watchdog was started and has not been kicked for
 * longer than its timeout in simulated time (b->t_s). The engine treats this
 * as a runtime failure, as the board would reset.
 */
bool hal_host_watchdog_expired(const hal_host_board *b);

/* ------------------------------------------------- CAN backend: SocketCAN */

/**
 * Open a non-blocking PF_CAN/SOCK_RAW/CAN_RAW socket bound to @p iface
 * (classic 11-bit frames; CAN_RAW_LOOPBACK on so other local sockets see our
 * frames, CAN_RAW_RECV_OWN_MSGS off so we never receive our own frames;
 * extended and FD frames are skipped on receive). The error filter
 * (CAN_RAW_ERR_FILTER) passes the controller's bus-off and restarted error
 * frames: they set and clear the bus-off state (state()), never reach recv's
 * caller. wait_rx polls the socket (ppoll), so recv() stays silent while the
 * bus is idle.
 * @param[out] out backend to assign to hal_host_board.can
 * @return 0, or a negative errno: -EAFNOSUPPORT (97) when the kernel has no
 *         CAN support, -ENODEV for an unknown interface, -EINVAL for a bad name.
 */
int hal_host_socketcan_open(const char *iface, hal_host_can_backend *out);

/** Close a backend opened by hal_host_socketcan_open (idempotent; clears *b). */
void hal_host_socketcan_close(hal_host_can_backend *b);

/* -------------------------------------------- CAN backend: in-memory pair */

#define HAL_HOST_CAN_QUEUE_LEN 256u /**< frames per direction */

/** A ring buffer of frames (one direction). */
typedef struct {
    hal_can_frame frame[HAL_HOST_CAN_QUEUE_LEN];
    uint32_t head;    /**< next frame to take */
    uint32_t count;   /**< frames waiting */
    uint32_t dropped; /**< pushes refused because the ring was full */
} hal_host_can_queue;

/** Two rings: frames to the drive (injected by a test) and from the drive. */
typedef struct {
    hal_host_can_queue to_drive;
    hal_host_can_queue from_drive;
    bool bus_off;            /**< injected bus-off: sends fail (HAL_EIO), frames to the drive are lost */
    uint32_t bus_off_count;  /**< bus-off entries injected */
    uint32_t lost_bus_off;   /**< frames to the drive dropped while bus-off */
} hal_host_can_loopback;

/**
 * Empty both rings of @p q and make @p out a backend whose send() fills
 * q->from_drive and whose recv() drains q->to_drive (no wait_rx: tests
 * inject frames between ticks, nothing to wait for).
 */
void hal_host_can_loopback_init(hal_host_can_loopback *q, hal_host_can_backend *out);

/** Queue a frame TO the drive. @return HAL_OK, HAL_EBUSY (full), HAL_EINVAL (id > 0x7FF, dlc > 8). */
int hal_host_can_loopback_inject(hal_host_can_loopback *q, const hal_can_frame *f);

/** Take the oldest frame FROM the drive. @return HAL_OK or HAL_EAGAIN (none). */
int hal_host_can_loopback_take(hal_host_can_loopback *q, hal_can_frame *f);

/**
 * Inject a bus-off (@p on true: the controller leaves the bus, counted once
 * per entry) or its end (@p on false: recovered, back on the bus). While
 * bus-off the drive's sends fail with HAL_EIO and frames queued to it are
 * dropped on receive, as a controller off the bus sees nothing.
 */
void hal_host_can_loopback_set_bus_off(hal_host_can_loopback *q, bool on);

#ifdef __cplusplus
}
#endif

#endif /* HAL_HOST_HAL_HOST_H */
