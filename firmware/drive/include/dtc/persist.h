/**
 * @file persist.h
 * @brief The parameter store: two NVM slots of records with a sequence number
 *        and CRC-32, behind a narrow interface to the values' owner.
 *
 * The NVM (hal_nvm_*) is split into two equal slots. A slot holds a header
 * and a payload of records, one per stored value:
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
 * previous set valid; at boot the valid slot with the newest sequence number
 * (serial arithmetic) wins.
 *
 * The store knows the NVM and this format, nothing of what the values mean:
 * the owner (persist_params; the drive's is drive_params.c) hands it the
 * values to save as records and takes a stored set's records back, refusing
 * those the present firmware does not accept (an unknown key, a value out of
 * range), which the store then counts as skipped. Context: BG only.
 */
#ifndef DTC_PERSIST_H
#define DTC_PERSIST_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

#define PERSIST_MAGIC 0x50435444u /**< "DTCP" */
/** Format 2: the configuration is derived from the ratings (the mask of set
 *  values 0x2321 stored with them); a format-1 set, whose derivable values
 *  were all absolute, is not loaded (PERSIST_OLD_FORMAT). */
#define PERSIST_FORMAT 2u
#define PERSIST_HEADER_SIZE 20u
#define PERSIST_RECORD_HEADER 4u /**< index, subindex, length */
#define PERSIST_VALUE_MAX 4u     /**< longest value the store hands back, bytes (a longer record is skipped) */

/** What the drive knows about its stored parameter set (parameter persist_status). */
typedef enum {
    PERSIST_LOADED = 0,      /**< the stored set is in use (loaded at boot or saved since) */
    PERSIST_EMPTY = 1,       /**< nothing stored (erased NVM): defaults */
    PERSIST_RECOVERED = 2,   /**< one slot corrupt (e.g. an interrupted save): the other slot's set is in use */
    PERSIST_CORRUPT = 3,     /**< both slots corrupt: defaults, EMCY 0x6300 */
    PERSIST_PARTIAL = 4,     /**< loaded, but some records were skipped (unknown or refused) */
    PERSIST_NO_NVM = 5,      /**< the NVM could not be read: defaults */
    PERSIST_OLD_FORMAT = 6,  /**< only a set of an older store format (an older firmware's): not loaded,
                                  defaults (EMCY 0x6300) until a save; its values are not guessed at */
} persist_status;

/** One stored value: whose it is (a dictionary index and subindex) and its bytes. */
typedef struct {
    uint16_t index;
    uint8_t sub;
    uint8_t len;                      /**< bytes in value, 0..PERSIST_VALUE_MAX */
    uint8_t value[PERSIST_VALUE_MAX]; /**< CAN raw, little-endian, as on the bus */
} persist_record;

/**
 * What the store needs of the values' owner. Every hook is called in
 * background context from a persist_* function, never blocks, and none may be
 * NULL; ctx is the one given to persist_init.
 */
typedef struct {
    /**
     * The next value a save stores: the owner's first from *cursor (0 at the
     * start of a save), *cursor advanced past it.
     * @return 1 with *rec filled, 0 when there is none left, or a negative HAL
     *         status (the save is refused, nothing written).
     */
    int (*next)(void *ctx, uint32_t *cursor, persist_record *rec);
    /** The start of a load: every value to its default. */
    void (*defaults)(void *ctx);
    /** One record of the stored set. @return true if applied, false if refused (the store counts it skipped). */
    bool (*take)(void *ctx, const persist_record *rec);
    /**
     * The end of a load (also when no set was stored): check the values as a
     * whole and put them in use. @return the number of values it dropped
     * (a set it refuses as a whole, back at its defaults, counts one).
     */
    uint32_t (*finish)(void *ctx);
} persist_params;

/** The store: its owner's interface and what it knows of the stored set. */
typedef struct {
    const persist_params *params; /**< the values' owner (persist_init) */
    void *ctx;                    /**< passed to every hook */
    uint8_t status;               /**< persist_status */
    uint32_t saves;               /**< successful saves since boot */
} persist_state;

/** Bind the store to the owner of its values; status PERSIST_EMPTY until a load. Context: BG. */
void persist_init(persist_state *st, const persist_params *params, void *ctx);

/**
 * Every value to its default (params->defaults), then the records of the
 * newest valid stored set (params->take), then params->finish.
 * @return the persist_status (also kept in st->status). Context: BG.
 */
uint8_t persist_load(persist_state *st);

/** What a save stores. */
typedef enum {
    PERSIST_SAVE_VALUES = 0, /**< every value params->next lists */
    PERSIST_SAVE_EMPTY = 1,  /**< no value: every one at its default at the next load */
} persist_save_kind;

/**
 * Store a set (@p kind) in the slot not holding the newest one. The slot
 * image (header and records) is built in @p work: at least
 * PERSIST_HEADER_SIZE plus, per value, PERSIST_RECORD_HEADER and its length.
 * @return HAL_OK, HAL_ENOSPC (@p work or the slot too small), a negative
 *         status of params->next, or the NVM's; on an error the previous set
 *         stays valid. Context: BG.
 */
int persist_save(persist_state *st, persist_save_kind kind, uint8_t *work, size_t work_size);

/** CRC-32 (IEEE 802.3, reflected, as zlib): continue @p crc (start with 0) over @p len bytes. Context: ANY. */
uint32_t persist_crc32(uint32_t crc, const void *data, size_t len);

#ifdef __cplusplus
}
#endif

#endif /* DTC_PERSIST_H */
