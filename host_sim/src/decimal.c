/**
 * @file decimal.c
 * @brief Decimal numbers only (see sim/decimal.h).
 */
#include "sim/decimal.h"

#include <errno.h>
#include <math.h>
#include <stdlib.h>

static bool is_digit(char c) { return c >= '0' && c <= '9'; }

/* The length of the longest run of digits at @p s. */
static size_t digits(const char *s)
{
    size_t n = 0;
    while (is_digit(s[n]))
        n++;
    return n;
}

/* The grammar is matched first, so strtod only ever sees a plain decimal
 * number (it would also take hexadecimal, inf, nan and leading blanks). */
static bool matches_grammar(const char *s)
{
    size_t i = 0;
    if (s[i] == '+' || s[i] == '-')
        i++;
    size_t whole = digits(s + i);
    i += whole;
    size_t frac = 0;
    if (s[i] == '.') {
        i++;
        frac = digits(s + i);
        i += frac;
    }
    if (whole == 0 && frac == 0)
        return false;
    if (s[i] == 'e' || s[i] == 'E') {
        i++;
        if (s[i] == '+' || s[i] == '-')
            i++;
        size_t ex = digits(s + i);
        if (ex == 0)
            return false;
        i += ex;
    }
    return s[i] == '\0';
}

bool sim_parse_decimal(const char *s, double *out)
{
    if (s == NULL || !matches_grammar(s))
        return false;
    errno = 0;
    char *end = NULL;
    double v = strtod(s, &end);
    if (*end != '\0' || errno == ERANGE || !isfinite(v))
        return false;
    *out = v;
    return true;
}
