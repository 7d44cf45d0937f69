/* ARM semihosting through BKPT 0xAB (for test images and debug prints): SYS_WRITEC,
 * SYS_WRITE0, SYS_EXIT and SYS_EXIT_EXTENDED. Anything else stops the run. */
#include "board_priv.h"

static uint32_t rd(board *b, int r) {
  uint32_t v = 0;
  uc_reg_read(b->uc, r, &v);
  return v;
}

int semihost_call(board *b) {
  uint32_t op = rd(b, UC_ARM_REG_R0), arg = rd(b, UC_ARM_REG_R1);
  switch (op) {
  case 0x03: { /* SYS_WRITEC */
    uint8_t c = 0;
    uc_mem_read(b->uc, arg, &c, 1);
    fputc(c, b->cfg.console);
    return 0;
  }
  case 0x04: { /* SYS_WRITE0 */
    for (uint32_t i = 0; i < 4096; i++) {
      uint8_t c = 0;
      if (uc_mem_read(b->uc, arg + i, &c, 1) != UC_ERR_OK || c == 0) break;
      fputc(c, b->cfg.console);
    }
    fflush(b->cfg.console);
    return 0;
  }
  case 0x18: /* SYS_EXIT: r1 is the reason; ADP_Stopped_ApplicationExit (0x20026) is success */
    b->exited = true;
    b->exit_code = arg == 0x20026u ? 0 : 1;
    return 0;
  case 0x20: { /* SYS_EXIT_EXTENDED: r1 -> {reason, code} */
    uint32_t blk[2] = {0, 0};
    uc_mem_read(b->uc, arg, blk, 8);
    b->exited = true;
    b->exit_code = blk[0] == 0x20026u ? (int)blk[1] : 1;
    return 0;
  }
  }
  board_fault(b, "semihosting operation 0x%02X is not supported", op);
  return -1;
}
