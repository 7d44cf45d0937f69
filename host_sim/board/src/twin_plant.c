/* The plant on the board's pins: the 12 HRTIM outputs switch the NPC legs, the ADC converts the
 * sensors at its sampling instants, and a logic analyser watches the gate signals.
 *
 * Time: the plant is integrated lazily up to the instant something needs it (an ADC sampling
 * instant, a period start, an output enable/disable, the end of a run) over the segments between
 * output edges (twin_sync), so every switching instant, dead time included, is honoured exactly.
 *
 * Gate wiring of the interface board (docs/board.md pin map, k_wiring below): per leg, timer
 * A/C/E output 1 drives S3 and output 2 S1, timer B/D/F output 1 drives S2 and output 2 S4 (the
 * inner switches on output 1, so the fault line's external event can reset them). The levels are
 * handled in switch order, bit 4 x leg + {S1, S3, S2, S4}.
 *
 * Leg state per segment: S1+S2 = P, S2+S3 = O, S3+S4 = N, all off =
 * PLANT_LEG_OFF (diodes). During a dead time only S2, or only S3, is on and the leg's voltage is
 * set by the sign of its current at the segment start (the plant takes one state per leg and
 * segment): only S2: a current into the motor flows through the upper clamp diode and S2 (O), a
 * current out of it through the free-wheeling diodes of S2 and S1 (P); only S3: into the motor
 * through the diodes of S4 and S3 (N), out of it through S3 and the lower clamp diode (O). A zero
 * current keeps the last defined state. Overlapping pairs and other combinations are counted as
 * violations and the leg keeps its last state.
 *
 * Sensor pins (docs/board.md): ia/ib/ic on PA0/PA1/PB1 at 1.65 V + i x 1.65 V / 150 A (90.91 A/V),
 * vc1/vc2 on PC0/PC1 at v x 3.3 V / 500 V (151.5 V/V). The plant's sensor model (gain, offset,
 * noise, then its own 12-bit quantisation with the same full scales) gives the values in A and V;
 * the ADC model quantises the pin voltage again (an exact round trip for the ideal scaling). */
#include "board_priv.h"
#include "board_twin/twin.h"
#include <math.h>
#include <stdlib.h>
#include <string.h>

#define EPS_T 1e-12

struct twin_bind {
  plant_state ps;
  double t;                  /* plant time = board time of the last sync */
  uint32_t levels;           /* gate levels of the segment that ended at t */
  bool levels_valid;
  uint8_t leg[3];            /* last defined leg state */
  uint8_t last_pon[3];       /* last P/O/N state, PLANT_LEG_OFF: none (after a long gates-off) */
  double off_since[3];       /* start of the present all-off interval */
  double last_on[12], last_off[12];
  board_la_stats la;
  double sens_t;             /* cached sensor reading */
  double sens_i[3], sens_v[2];
};

static struct twin_bind *bind(board *b) { return b->bind; }

/* HRTIM output o (TA1, TA2, TB1, ... TF2) -> switch bit (4 x leg + 0 S1, 1 S3, 2 S2, 3 S4). */
static const uint8_t k_wiring[12] = {1, 0, 2, 3, 5, 4, 6, 7, 9, 8, 10, 11};

/* The 12 gate signals at time t, in switch order. */
static uint32_t switch_levels(board *b, double t) {
  uint32_t out = hrtim_levels(b, t), sw = 0;
  for (int o = 0; o < 12; o++) sw |= ((out >> o) & 1u) << k_wiring[o];
  return sw;
}

int board_attach_plant(board *b, const plant_config *cfg) {
  struct twin_bind *w = calloc(1, sizeof *w);
  int rc = plant_init(&w->ps, cfg);
  if (rc != 0) { free(w); return rc; }
  w->t = board_now(b);
  w->ps.t_s = w->t;
  for (int l = 0; l < 3; l++) w->leg[l] = w->last_pon[l] = PLANT_LEG_OFF;
  for (int o = 0; o < 12; o++) {
    w->last_on[o] = w->last_off[o] = -1;
    w->la.first_on_s[o] = w->la.last_off_s[o] = -1;
    w->la.min_on_s[o] = w->la.min_off_s[o] = INFINITY;
  }
  w->la.min_dead_time_s = INFINITY;
  w->la.mark_s = -1;
  w->sens_t = -1;
  free(b->bind);
  b->bind = w;
  return 0;
}

void twin_free(board *b) { free(b->bind); b->bind = NULL; }

static uint8_t leg_state(struct twin_bind *w, int l, uint32_t lv, double i_leg) {
  unsigned s1 = (lv >> (4 * l)) & 1u, s3 = (lv >> (4 * l + 1)) & 1u, s2 = (lv >> (4 * l + 2)) & 1u,
           s4 = (lv >> (4 * l + 3)) & 1u;
  unsigned k = s1 | (s2 << 1) | (s3 << 2) | (s4 << 3);
  switch (k) {
  case 0x3: return PLANT_LEG_P;   /* S1 S2 */
  case 0x6: return PLANT_LEG_O;   /* S2 S3 */
  case 0xC: return PLANT_LEG_N;   /* S3 S4 */
  case 0x0: return PLANT_LEG_OFF; /* all off */
  case 0x2:                       /* S2 only: dead time between P and O */
    return i_leg > 0 ? PLANT_LEG_O : i_leg < 0 ? PLANT_LEG_P : w->leg[l];
  case 0x4:                       /* S3 only: dead time between O and N */
    return i_leg > 0 ? PLANT_LEG_N : i_leg < 0 ? PLANT_LEG_O : w->leg[l];
  default:
    if ((s1 && s3) || (s2 && s4)) w->la.overlaps++;
    else w->la.bad_combinations++;
    return w->leg[l];
  }
}

/* Edges between the previous segment's levels and this one's, at time t. */
static void la_edges(struct twin_bind *w, double t, uint32_t lv) {
  uint32_t prev = w->levels_valid ? w->levels : 0u;
  uint32_t ch = lv ^ prev;
  for (int o = 0; o < 12; o++) {
    if (!(ch & (1u << o))) continue;
    if (lv & (1u << o)) {
      w->la.on_edges[o]++;
      if (w->last_off[o] >= 0 && t - w->last_off[o] < w->la.min_off_s[o]) w->la.min_off_s[o] = t - w->last_off[o];
      w->last_on[o] = t;
      if (w->la.first_on_s[o] < 0) w->la.first_on_s[o] = t;
      int partner = o ^ 1; /* S1<->S3, S2<->S4: outputs 1 and 2 of one timer */
      if (w->last_off[partner] >= 0 && !(lv & (1u << partner)) && w->last_off[partner] >= w->last_on[partner]) {
        double dt = t - w->last_off[partner];
        if (dt < 50e-6) { /* a commutation of the pair (not a long off period) */
          w->la.dead_time_events++;
          if (dt < w->la.min_dead_time_s) w->la.min_dead_time_s = dt;
          if (dt > w->la.max_dead_time_s) w->la.max_dead_time_s = dt;
        }
      }
    } else {
      w->la.off_edges[o]++;
      if (w->la.mark_s >= 0 && t >= w->la.mark_s - EPS_T && w->la.off_after_mark_s[o] < 0) w->la.off_after_mark_s[o] = t;
      w->last_off[o] = t;
      w->la.last_off_s[o] = t;
      if (w->last_on[o] >= 0) {
        w->la.on_time_s[o] += t - w->last_on[o];
        if (t - w->last_on[o] < w->la.min_on_s[o]) w->la.min_on_s[o] = t - w->last_on[o];
      }
    }
  }
  w->levels = lv;
  w->levels_valid = true;
}

void twin_sync(board *b, double t) {
  struct twin_bind *w = bind(b);
  if (!w) { hrtim_prune(b, t); return; }
  adc_advance(b, t); /* ADC sampling instants before t take the plant there first */
  while (w->t < t - EPS_T && !b->fault) {
    double tn = hrtim_next_edge(b, w->t);
    if (tn > t) tn = t;
    uint32_t lv = switch_levels(b, w->t);
    if (!w->levels_valid || lv != w->levels) la_edges(w, w->t, lv);
    uint8_t legs[3];
    double i_abc[3] = {0, 0, 0};
    for (int l = 0; l < 3; l++) {
      unsigned k = (lv >> (4 * l)) & 0xFu;
      if (k == 0x2u || k == 0x4u) { /* a dead time: the current's sign decides */
        plant_truth tr;
        plant_get_truth(&w->ps, &tr);
        i_abc[0] = tr.ia_A; i_abc[1] = tr.ib_A; i_abc[2] = tr.ic_A;
        break;
      }
    }
    for (int l = 0; l < 3; l++) {
      uint8_t s = leg_state(w, l, lv, i_abc[l]);
      /* P<->N without O in between; an all-off gap shorter than 50 us (both pairs commutating at
       * once, through their dead times) does not separate them, a longer gates-off does */
      if (s == PLANT_LEG_OFF && w->leg[l] != PLANT_LEG_OFF) w->off_since[l] = w->t;
      if (s != PLANT_LEG_OFF) {
        if (w->leg[l] == PLANT_LEG_OFF && w->t - w->off_since[l] >= 50e-6) w->last_pon[l] = PLANT_LEG_OFF;
        uint8_t p = w->last_pon[l];
        if ((s == PLANT_LEG_P && p == PLANT_LEG_N) || (s == PLANT_LEG_N && p == PLANT_LEG_P)) w->la.pn_steps++;
        w->last_pon[l] = s;
      }
      legs[l] = s;
      w->leg[l] = s;
    }
    plant_advance(&w->ps, legs, legs, 1.0, tn - w->t);
    w->t = tn;
    hrtim_prune(b, w->t);
  }
  if (w->t < t) w->t = t;
  w->la.t_s = w->t;
}

plant_state *board_plant(board *b) {
  if (!bind(b)) return NULL;
  twin_sync(b, board_now(b));
  return &bind(b)->ps;
}

double twin_pin_voltage(board *b, char port, int pin, double t) {
  struct twin_bind *w = bind(b);
  double i[3] = {0, 0, 0}, v[2] = {0, 0};
  if (w) {
    twin_sync(b, t);
    if (w->sens_t != t) {
      plant_adc adc;
      plant_sample(&w->ps, &adc);
      plant_adc_to_units(&w->ps.cfg, &adc, w->sens_i, w->sens_v);
      w->sens_t = t;
    }
    memcpy(i, w->sens_i, sizeof i);
    memcpy(v, w->sens_v, sizeof v);
  }
  const double ki = 1.65 / 150.0, kv = 3.3 / 500.0; /* docs/board.md: 90.91 A/V, 151.5 V/V */
  if (port == 'A' && pin == 0) return 1.65 + i[0] * ki;
  if (port == 'A' && pin == 1) return 1.65 + i[1] * ki;
  if (port == 'B' && pin == 1) return 1.65 + i[2] * ki;
  if (port == 'C' && pin == 0) return v[0] * kv;
  if (port == 'C' && pin == 1) return v[1] * kv;
  return 0.0;
}

void board_drive_fault_line(board *b, int level) {
  board_drive_pin(b, 'B', 10, level);
  board_drive_pin(b, 'B', 5, level);
}

uint32_t board_gate_levels(board *b) {
  double now = board_now(b);
  twin_sync(b, now);
  return switch_levels(b, now);
}

void board_la_mark(board *b) {
  struct twin_bind *w = bind(b);
  if (!w) return;
  double now = board_now(b);
  twin_sync(b, now);
  w->la.mark_s = now;
  w->la.on_at_mark = switch_levels(b, now);
  for (int o = 0; o < 12; o++) w->la.off_after_mark_s[o] = -1;
}

void board_la_get(board *b, board_la_stats *out) {
  struct twin_bind *w = bind(b);
  if (!w) { memset(out, 0, sizeof *out); return; }
  twin_sync(b, board_now(b));
  *out = w->la;
  for (int o = 0; o < 12; o++) /* count a pulse still on up to now */
    if ((w->levels >> o) & 1u && w->last_on[o] >= 0) out->on_time_s[o] += w->t - w->last_on[o];
}
