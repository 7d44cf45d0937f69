/* g_drive field offsets in the target's layout (fw_layout.c). */
#ifndef BOARD_FW_LAYOUT_H
#define BOARD_FW_LAYOUT_H
#include <stddef.h>
typedef struct {
  size_t cfg_size, cfg_period_s, cfg_speed_mode, speed_mode_size, cfg_rbfn_m_w, cfg_active, period_cycles;
  size_t speed_ref_rad_s, run, clear_faults_req, tick, snap, snap_size, timing_overruns;
} fw_layout;
const fw_layout *fw_layout_get(void);
#endif
