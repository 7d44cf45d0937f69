/**
 * @file semihost.h
 * @brief ARM semihosting for the PIL programs under qemu-system-arm
 *        (-semihosting-config enable=on,target=native).
 *
 * Semihosting traps to the debugger/emulator with BKPT 0xAB; QEMU then does
 * the host-side work. Output arrives on QEMU's stderr. Calls block the
 * emulated core, so they belong outside measured code. Context: thread mode.
 */
#ifndef PIL_SEMIHOST_H
#define PIL_SEMIHOST_H

#include <stddef.h>
#include <stdint.h>

/** Print a NUL-terminated string (SYS_WRITE0). */
void semihost_write0(const char *s);

/**
 * Fetch the command line given by QEMU's -semihosting-config arg=... into
 * @p buf (SYS_GET_CMDLINE). @return 0 on success, -1 if none or too long.
 */
int semihost_cmdline(char *buf, size_t size);

/** Open host file @p path for binary reading (SYS_OPEN, mode "rb").
 *  @return a handle >= 0, or -1. */
int semihost_open_read(const char *path);

/** Read up to @p len bytes (SYS_READ). @return bytes read (0 at the end), or -1. */
int32_t semihost_read(int handle, void *buf, uint32_t len);

/** Length of an open file, bytes (SYS_FLEN). @return -1 on error. */
int32_t semihost_flen(int handle);

/** Close a handle (SYS_CLOSE). */
void semihost_close(int handle);

/** End the emulation with exit status @p code (SYS_EXIT_EXTENDED). */
__attribute__((noreturn)) void semihost_exit(int code);

/* ---- a small line builder, so the PIL programs need no printf ---- */

typedef struct {
    char buf[256];
    size_t len;
} pil_line;

void line_str(pil_line *l, const char *s);
void line_u32(pil_line *l, uint32_t v);
/** @p v in hex with 0x and 8 digits. */
void line_hex32(pil_line *l, uint32_t v);
/** @p tenths / 10 with one decimal, e.g. 1234 -> "123.4". */
void line_tenths(pil_line *l, uint32_t tenths);
/** Print the line with a newline, then clear it. */
void line_flush(pil_line *l);

#endif /* PIL_SEMIHOST_H */
