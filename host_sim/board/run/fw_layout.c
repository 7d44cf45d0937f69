/* Offsets of the g_drive fields the twin's test-only RAM path touches, as the target compiler
 * lays them out: arm-none-eabi uses short enums (AAPCS "variable-size enumerated types"), so
 * this file alone is compiled with -fshort-enums (see CMakeLists.txt). Only plain numbers
 * leave it. */
#include "fw_layout.h"
#include <stddef.h>
#include "dtc/drive.h"

#define CFG_FIELD(f) ((size_t)offsetof(drive, cfg) + offsetof(ctl_cfg, f))

const fw_layout *fw_layout_get(void) {
  static const fw_layout l = {
    .cfg_size = sizeof(ctl_cfg),
    .cfg_period_s = CFG_FIELD(period_s),
    .cfg_speed_mode = CFG_FIELD(speed.mode),
    .speed_mode_size = sizeof(((ctl_cfg *)0)->speed.mode),
    .cfg_rbfn_m_w = CFG_FIELD(speed.rbfn.m_w),
    .cfg_active = offsetof(drive, cfg_active),
    .period_cycles = offsetof(drive, period_cycles),
    .speed_ref_rad_s = offsetof(drive, speed_ref_rad_s),
    .run = offsetof(drive, run),
    .clear_faults_req = offsetof(drive, clear_faults_req),
    .tick = offsetof(drive, tick),
    .snap = offsetof(drive, snap),
    .snap_size = sizeof(drive_snapshot),
    .timing_overruns = offsetof(drive, timing.overruns),
  };
  return &l;
}
