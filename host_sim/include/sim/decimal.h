/**
 * @file decimal.h
 * @brief The one number syntax of dtc-sim's command line and scenario files.
 *
 * A number is written in decimal only:
 *     [+|-] DIGITS [. [DIGITS]] [(e|E) [+|-] DIGITS]
 *   | [+|-] . DIGITS [(e|E) [+|-] DIGITS]
 * e.g. 500, -0.25, .5, 2e-3, 1.5E+2. Not accepted: hexadecimal (0x10) and
 * hexadecimal floating point (0x1p-4), inf, infinity and nan, blanks, digit
 * separators, anything after the number, and values a double does not hold
 * (1e400, and 1e-400, which strtod flags as out of range). A key that takes a
 * word as well says so itself (e.g. `--duration inf`).
 */
#ifndef SIM_DECIMAL_H
#define SIM_DECIMAL_H

#include <stdbool.h>

#ifdef __cplusplus
extern "C" {
#endif

/**
 * Read @p s as a decimal number (the grammar above: the whole string), then
 * convert it with strtod.
 * @return true with the value in @p out; false (out unchanged) when @p s is
 *         not a decimal number or strtod finds it out of range (ERANGE).
 */
bool sim_parse_decimal(const char *s, double *out);

#ifdef __cplusplus
}
#endif

#endif /* SIM_DECIMAL_H */
