/* Exact instruction counts of every exception handler: the instructions executed between its
 * entry and its return, less those of exceptions that preempted it (stacking and unstacking
 * are done by the host and cost no instructions here; a Cortex-M4 adds 12 + 10 cycles). */
#include "board_priv.h"
#include "board_twin/twin.h"
#include <string.h>

static uint64_t instr(const board *b) { return b->cycles - b->idle; }

void irqstat_enter(board *b, int exc) {
  irq_stats *s = &b->irq;
  if (s->depth >= IRQSTAT_DEPTH) return;
  s->stack[s->depth].exc = exc;
  s->stack[s->depth].start = instr(b);
  s->stack[s->depth].nested = 0;
  s->depth++;
}

void irqstat_exit(board *b, int exc) {
  irq_stats *s = &b->irq;
  if (s->depth == 0 || s->stack[s->depth - 1].exc != exc) { s->depth = 0; return; }
  s->depth--;
  uint64_t total = instr(b) - s->stack[s->depth].start;
  uint64_t own = total - s->stack[s->depth].nested;
  if (s->depth > 0) s->stack[s->depth - 1].nested += total;
  board_irq_stat *st = &s->per[exc];
  if (st->count == 0 || own < st->best) st->best = own;
  if (own > st->worst) st->worst = own;
  st->count++;
  st->total += own;
}

void board_irq_get(board *b, int exc, board_irq_stat *out) {
  if (exc < 0 || exc >= NUM_EXC) { memset(out, 0, sizeof *out); return; }
  *out = b->irq.per[exc];
}
