/**
 * @file semihost.c
 * @brief ARM semihosting calls (write, command line, exit) and a line builder.
 */
#include "semihost.h"

#define SYS_OPEN 0x01
#define SYS_CLOSE 0x02
#define SYS_WRITE0 0x04
#define SYS_READ 0x06
#define SYS_FLEN 0x0C
#define SYS_GET_CMDLINE 0x15
#define SYS_EXIT_EXTENDED 0x20
#define ADP_STOPPED_APPLICATION_EXIT 0x20026u

static int semihost_call(int op, void *arg)
{
    register int r0 __asm("r0") = op;
    register void *r1 __asm("r1") = arg;
    __asm volatile("bkpt 0xAB" : "+r"(r0) : "r"(r1) : "memory");
    return r0;
}

void semihost_write0(const char *s) { (void)semihost_call(SYS_WRITE0, (void *)(uintptr_t)s); }

int semihost_cmdline(char *buf, size_t size)
{
    uint32_t block[2] = {(uint32_t)(uintptr_t)buf, (uint32_t)size};
    if (size == 0u)
        return -1;
    if (semihost_call(SYS_GET_CMDLINE, block) != 0) {
        buf[0] = '\0';
        return -1;
    }
    return 0;
}

int semihost_open_read(const char *path)
{
    uint32_t n = 0u;
    while (path[n] != '\0')
        n++;
    /* Mode 1 = "rb" (ARM semihosting, SYS_OPEN). */
    uint32_t block[3] = {(uint32_t)(uintptr_t)path, 1u, n};
    return semihost_call(SYS_OPEN, block);
}

int32_t semihost_read(int handle, void *buf, uint32_t len)
{
    uint32_t block[3] = {(uint32_t)handle, (uint32_t)(uintptr_t)buf, len};
    int left = semihost_call(SYS_READ, block); /* bytes NOT read */
    if (left < 0 || (uint32_t)left > len)
        return -1;
    return (int32_t)(len - (uint32_t)left);
}

int32_t semihost_flen(int handle)
{
    uint32_t block[1] = {(uint32_t)handle};
    return semihost_call(SYS_FLEN, block);
}

void semihost_close(int handle)
{
    uint32_t block[1] = {(uint32_t)handle};
    (void)semihost_call(SYS_CLOSE, block);
}

void semihost_exit(int code)
{
    uint32_t block[2] = {ADP_STOPPED_APPLICATION_EXIT, (uint32_t)code};
    (void)semihost_call(SYS_EXIT_EXTENDED, block);
    for (;;) {
    }
}

/* ------------------------------------------------------------ line builder */

static void line_char(pil_line *l, char c)
{
    if (l->len + 1u < sizeof l->buf)
        l->buf[l->len++] = c;
}

void line_str(pil_line *l, const char *s)
{
    while (*s != '\0')
        line_char(l, *s++);
}

void line_u32(pil_line *l, uint32_t v)
{
    char digits[10];
    unsigned n = 0u;
    do {
        digits[n++] = (char)('0' + v % 10u);
        v /= 10u;
    } while (v != 0u);
    while (n > 0u)
        line_char(l, digits[--n]);
}

void line_hex32(pil_line *l, uint32_t v)
{
    static const char hex[] = "0123456789abcdef";
    line_str(l, "0x");
    for (int shift = 28; shift >= 0; shift -= 4)
        line_char(l, hex[(v >> shift) & 0xFu]);
}

void line_tenths(pil_line *l, uint32_t tenths)
{
    line_u32(l, tenths / 10u);
    line_char(l, '.');
    line_char(l, (char)('0' + tenths % 10u));
}

void line_flush(pil_line *l)
{
    /* A full line is cut, never its end. */
    if (l->len + 2u > sizeof l->buf)
        l->len = sizeof l->buf - 2u;
    l->buf[l->len++] = '\n';
    l->buf[l->len] = '\0';
    semihost_write0(l->buf);
    l->len = 0u;
}
