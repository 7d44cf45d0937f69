/* docs/board.md pin table parser and the check of the firmware's GPIO configuration. */
#include "board_twin/pinmap.h"
#include <ctype.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static const char *k_modes[4] = {"Input", "Output", "AF", "Analog"};

static char *trim(char *s) {
  while (isspace((unsigned char)*s)) s++;
  size_t n = strlen(s);
  while (n && isspace((unsigned char)s[n - 1])) s[--n] = 0;
  return s;
}

/* Split "| a | b | c |" into cells; returns the count. */
static int cells(char *line, char **out, int max) {
  char *s = trim(line);
  if (*s != '|') return 0;
  s++;
  int n = 0;
  while (*s && n < max) {
    char *bar = strchr(s, '|');
    if (!bar) break;
    *bar = 0;
    out[n++] = trim(s);
    s = bar + 1;
  }
  return n;
}

int pinmap_parse(const char *path, pinmap_row *rows, size_t max, char *err, size_t n) {
  FILE *f = fopen(path, "r");
  if (!f) { snprintf(err, n, "%s:0: cannot open", path); return -1; }
  char line[512];
  int lineno = 0, state = 0; /* 0 looking for the header, 1 separator, 2 rows */
  int count = 0;
  while (fgets(line, sizeof line, f)) {
    lineno++;
    line[strcspn(line, "\r\n")] = 0;
    if (state == 0) {
      if (strcmp(trim(line), "| Pin | Mode | AF | Signal | Scaling |") == 0) state = 1;
      continue;
    }
    char *c[8];
    int nc = cells(line, c, 8);
    if (state == 1) {
      if (nc != 5 || strspn(c[0], "-: ") != strlen(c[0])) { snprintf(err, n, "%s:%d: expected the table's separator row", path, lineno); goto fail; }
      state = 2;
      continue;
    }
    if (nc == 0) break; /* end of the table */
    if (nc != 5) { snprintf(err, n, "%s:%d: a row needs 5 cells, found %d", path, lineno, nc); goto fail; }
    if ((size_t)count >= max) { snprintf(err, n, "%s:%d: more than %zu rows", path, lineno, max); goto fail; }
    pinmap_row *r = &rows[count];
    memset(r, 0, sizeof *r);
    char *end;
    if (c[0][0] != 'P' || c[0][1] < 'A' || c[0][1] > 'G' || !isdigit((unsigned char)c[0][2])) {
      snprintf(err, n, "%s:%d: pin '%s' is not like PA8", path, lineno, c[0]); goto fail;
    }
    r->port = c[0][1];
    r->pin = (int)strtol(c[0] + 2, &end, 10);
    if (*end || r->pin > 15) { snprintf(err, n, "%s:%d: pin '%s' is not like PA8", path, lineno, c[0]); goto fail; }
    r->mode = -1;
    for (int m = 0; m < 4; m++)
      if (strcmp(c[1], k_modes[m]) == 0) r->mode = m;
    if (r->mode < 0) { snprintf(err, n, "%s:%d: mode '%s' is not AF, Analog, Input or Output", path, lineno, c[1]); goto fail; }
    if (strcmp(c[2], "-") == 0) r->af = -1;
    else {
      r->af = (int)strtol(c[2], &end, 10);
      if (!*c[2] || *end || r->af < 0 || r->af > 15) { snprintf(err, n, "%s:%d: AF '%s' is not 0-15 or -", path, lineno, c[2]); goto fail; }
    }
    if ((r->mode == 2) != (r->af >= 0)) { snprintf(err, n, "%s:%d: AF must be a number exactly when the mode is AF", path, lineno); goto fail; }
    for (int k = 0; k < count; k++)
      if (rows[k].port == r->port && rows[k].pin == r->pin) { snprintf(err, n, "%s:%d: P%c%d listed twice", path, lineno, r->port, r->pin); goto fail; }
    snprintf(r->signal, sizeof r->signal, "%s", c[3]);
    count++;
  }
  fclose(f);
  if (state != 2) { snprintf(err, n, "%s:%d: no table with the header | Pin | Mode | AF | Signal | Scaling |", path, lineno); return -1; }
  return count;
fail:
  fclose(f);
  return -1;
}

int pinmap_check(const pinmap_row *rows, size_t nrows, const board_pin *pins, size_t npins, FILE *report) {
  int bad = 0;
  for (size_t i = 0; i < npins; i++) {
    const board_pin *p = &pins[i];
    const pinmap_row *r = NULL;
    for (size_t k = 0; k < nrows; k++)
      if (rows[k].port == p->port && rows[k].pin == p->pin) r = &rows[k];
    if (!r) {
      if (p->changed) {
        bad++;
        if (report) fprintf(report, "P%c%d: configured by the firmware as %s%s but not in the table\n", p->port, p->pin,
                            k_modes[p->mode], p->mode == 2 ? " (AF)" : "");
      }
      continue;
    }
    if (p->mode != r->mode || (r->mode == 2 && p->af != r->af)) {
      bad++;
      if (report) {
        fprintf(report, "P%c%d (%s): table says %s", p->port, p->pin, r->signal, k_modes[r->mode]);
        if (r->mode == 2) fprintf(report, " AF%d", r->af);
        fprintf(report, ", firmware left %s", k_modes[p->mode]);
        if (p->mode == 2) fprintf(report, " AF%d", p->af);
        fprintf(report, "\n");
      }
    }
  }
  return bad;
}
