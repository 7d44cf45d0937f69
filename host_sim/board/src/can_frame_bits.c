/* Length on the wire of a classic CAN base-format frame (ISO 11898-1, "Data frame" / "Remote
 * frame"): SOF, 11-bit identifier, RTR, IDE, r0, DLC, data, 15-bit CRC, all bit-stuffed (a
 * complementary bit after five equal bits), then CRC delimiter, ACK slot and delimiter, EOF (7)
 * and the intermission (3), which are not stuffed. Used for the emulated transmission times. */
#include "board_priv.h"

unsigned can_frame_bits(uint16_t id, bool rtr, unsigned dlc, const uint8_t *data) {
  uint8_t bits[1 + 11 + 3 + 4 + 64 + 15];
  unsigned n = 0;
  bits[n++] = 0; /* SOF, dominant */
  for (int i = 10; i >= 0; i--) bits[n++] = (uint8_t)((id >> i) & 1u);
  bits[n++] = rtr ? 1 : 0;
  bits[n++] = 0; /* IDE: base format */
  bits[n++] = 0; /* r0 */
  for (int i = 3; i >= 0; i--) bits[n++] = (uint8_t)((dlc >> i) & 1u);
  unsigned bytes = rtr ? 0 : (dlc > 8 ? 8 : dlc);
  for (unsigned k = 0; k < bytes; k++)
    for (int i = 7; i >= 0; i--) bits[n++] = (uint8_t)((data[k] >> i) & 1u);
  uint32_t crc = 0; /* CRC-15 over SOF..data, generator 0x4599 */
  for (unsigned k = 0; k < n; k++) {
    unsigned nxt = bits[k] ^ ((crc >> 14) & 1u);
    crc = (crc << 1) & 0x7FFFu;
    if (nxt) crc ^= 0x4599u;
  }
  for (int i = 14; i >= 0; i--) bits[n++] = (uint8_t)((crc >> i) & 1u);
  unsigned stuffed = n, run = 1;
  for (unsigned k = 1; k < n; k++) {
    run = bits[k] == bits[k - 1] ? run + 1 : 1;
    if (run == 5) { /* a complementary stuff bit follows (also after the last CRC bit) */
      stuffed++;
      if (k + 1 >= n) break;
      k++; /* the next bit runs on from the stuff bit, which differs from bits[k - 1] */
      run = bits[k] != bits[k - 1] ? 2 : 1;
    }
  }
  return stuffed + 1 + 2 + 7 + 3;
}
