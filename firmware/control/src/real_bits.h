/**
 * @file real_bits.h
 * @brief Tests on the IEEE single-precision bits of a real_t, for the
 *        control step's hot path (private to firmware/control/src): a finite
 *        test without isfinite(), and compares as integers where a float
 *        compare would cost more. Every function is pure; Context: ANY.
 */
#ifndef DTC_REAL_BITS_H
#define DTC_REAL_BITS_H

#include <stdbool.h>
#include <stdint.h>
#include <string.h>

#include "dtc/num.h"

_Static_assert(sizeof(real_t) == sizeof(uint32_t), "real_t is IEEE single precision");

/** True when @p x is finite: NaN and +-inf give NaN on subtraction. */
static inline bool finite_r(real_t x) { return (x - x) == R(0.0); }

/** The bits of @p x: for values >= +0 they order like the values; a negative
 *  value's (sign bit set) are above every positive one's, a NaN's above every
 *  finite positive one's. */
static inline uint32_t f32_bits(real_t x)
{
    uint32_t u;
    memcpy(&u, &x, sizeof u);
    return u;
}

/** The value of the bits @p u (f32_bits' inverse). */
static inline real_t f32_of_bits(uint32_t u)
{
    real_t x;
    memcpy(&x, &u, sizeof x);
    return x;
}

/** The magnitude bits of @p x: for finite values they order like |x|; a NaN
 *  or an infinity is above every finite value's. */
static inline uint32_t abs_bits(real_t x) { return f32_bits(x) & 0x7FFFFFFFu; }

#endif /* DTC_REAL_BITS_H */
