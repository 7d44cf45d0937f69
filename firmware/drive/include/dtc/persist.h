/**
 * @file persist.h
 * @brief Persistent parameters in two NVM slots with a sequence number and CRC-32.
 *
 * The NVM (hal_nvm_*) is split into two equal slots. A slot holds a header
 * and a payload of records, one per persistent parameter (CO_F_PERSIST):
 *
 *   header (PERSIST_HEADER_SIZE bytes, little-endian):
 *     0  u32 magic PERSIST_MAGIC     4  u16 format PERSIST_FORMAT
 *     6  u16 record count            8  u32 sequence number
 *     12 u32 payload length          16 u32 CRC-32 of bytes 0..15 and the payload
 *   record: u16 index, u8 subindex, u8 length n, n value bytes (CAN raw, as on the bus)
 *
 * A save writes the slot that does NOT hold the newest valid set, header and
 * payload in one write (one erase of each page); the header's CRC covers the
 * payload, so a power loss at any byte leaves that slot invalid and the
 * previous set valid; at boot the valid slot with the newest sequence number (serial
 * arithmetic) wins. Records are applied through the object dictionary's
 * checked path, so a record for an unknown parameter or with a value the
 * present firmware refuses is skipped, never applied. Context: BG only.
 */
#ifndef DTC_PERSIST_H
#define DTC_PERSIST_H

#include <stddef.h>
#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

struct drive;

#define PERSIST_MAGIC 0x50435444u /**< "DTCP" */
#define PERSIST_FORMAT 1u
#define PERSIST_HEADER_SIZE 20u

/** What the drive knows about its stored parameter set (parameter persist_status). */
typedef enum {
    PERSIST_LOADED = 0,      /**< the stored set is in use (loaded at boot or saved since) */
    PERSIST_EMPTY = 1,       /**< nothing stored (erased NVM): defaults */
    PERSIST_RECOVERED = 2,   /**< one slot corrupt (e.g. an interrupted save): the other slot's set is in use */
    PERSIST_CORRUPT = 3,     /**< both slots corrupt: defaults, EMCY 0x6300 */
    PERSIST_PARTIAL = 4,     /**< loaded, but some records were skipped (unknown or refused) */
    PERSIST_NO_NVM = 5,      /**< the NVM could not be read: defaults */
} persist_status;

typedef struct {
    uint8_t status;          /**< persist_status */
    uint32_t saves;          /**< successful saves since boot */
} persist_state;

/**
 * Set every parameter to its default, then apply the newest valid stored set.
 * Configuration changes are published with one drive_cfg_commit().
 * @return the persist_status (also kept in d->persist.status). Context: BG.
 */
uint8_t persist_load(struct drive *d);

/**
 * Store every persistent parameter's present value.
 * @return HAL_OK, or a negative HAL status (the previous set stays valid). Context: BG.
 */
int persist_save(struct drive *d);

/**
 * Store an empty set (every parameter at its default at the next boot).
 * @return HAL_OK or a negative HAL status. Context: BG.
 */
int persist_save_defaults(struct drive *d);

/** CRC-32 (IEEE 802.3, reflected, as zlib): continue @p crc (start with 0) over @p len bytes. Context: ANY. */
uint32_t persist_crc32(uint32_t crc, const void *data, size_t len);

#ifdef __cplusplus
}
#endif

#endif /* DTC_PERSIST_H */
