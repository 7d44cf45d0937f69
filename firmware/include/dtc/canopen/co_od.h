/**
 * @file co_od.h
 * @brief The CANopen object dictionary: typed entries generated from the one
 *        parameter table (tools/params/parameters.toml), and the checked
 *        read/write path every SDO, PDO and persisted value goes through.
 *
 * Every entry binds a CANopen object (index, subindex, CiA 301 data type) to
 * a C field: a member of ctl_cfg, of the communication or scope settings, of
 * the telemetry snapshot, a constant, or a handler (CO_BIND_FN). Values on
 * the bus are "CAN raw" values: raw = internal * k (k from the table's scale
 * and resolution, e.g. rpm per rad/s); limits and defaults are stored raw.
 *
 * A write is decoded, checked (length, access, NaN, range, allowed set,
 * device state, cross-field consistency) and only then applied, so a bad
 * request never changes anything. Configuration writes go through
 * drive_cfg_edit()/drive_cfg_commit(): the interrupt sees either the old or
 * the new configuration, never a mix.
 *
 * Context: everything here is background (BG) only.
 */
#ifndef DTC_CANOPEN_CO_OD_H
#define DTC_CANOPEN_CO_OD_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "dtc/ctl.h"

#ifdef __cplusplus
extern "C" {
#endif

struct drive;

/* ---------------------------------------------------- CiA 301 abort codes */
#define CO_ABORT_NONE 0x00000000u
#define CO_ABORT_TOGGLE 0x05030000u          /**< toggle bit not alternated */
#define CO_ABORT_TIMEOUT 0x05040000u         /**< SDO protocol timed out */
#define CO_ABORT_CMD 0x05040001u             /**< command specifier not valid or unknown */
#define CO_ABORT_WRITE_ONLY 0x06010001u      /**< attempt to read a write-only object */
#define CO_ABORT_READ_ONLY 0x06010002u       /**< attempt to write a read-only object */
#define CO_ABORT_NO_OBJECT 0x06020000u       /**< object does not exist */
#define CO_ABORT_PARAM_INCOMPAT 0x06040043u  /**< general parameter incompatibility */
#define CO_ABORT_LENGTH 0x06070010u          /**< data type does not match, length mismatch */
#define CO_ABORT_NO_SUB 0x06090011u          /**< subindex does not exist */
#define CO_ABORT_INVALID_VALUE 0x06090030u   /**< invalid value (NaN, not in the allowed set) */
#define CO_ABORT_VALUE_HIGH 0x06090031u      /**< value too high */
#define CO_ABORT_VALUE_LOW 0x06090032u       /**< value too low */
#define CO_ABORT_GENERAL 0x08000000u         /**< general error */
#define CO_ABORT_STORE 0x08000020u           /**< cannot be stored (wrong signature, NVM failure) */
#define CO_ABORT_STATE 0x08000022u           /**< refused in the present device state (running) */

/** CiA 301 data types used by the drive (the numbers are the EDS DataType codes). */
typedef enum {
    CO_DT_BOOLEAN = 0x01,
    CO_DT_INTEGER8 = 0x02,
    CO_DT_INTEGER16 = 0x03,
    CO_DT_INTEGER32 = 0x04,
    CO_DT_UNSIGNED8 = 0x05,
    CO_DT_UNSIGNED16 = 0x06,
    CO_DT_UNSIGNED32 = 0x07,
    CO_DT_REAL32 = 0x08,
    CO_DT_VISIBLE_STRING = 0x09,
    CO_DT_DOMAIN = 0x0F,
} co_dtype;

/** Entry flags. */
enum co_flag {
    CO_F_READ = 1u << 0,    /**< readable by SDO */
    CO_F_WRITE = 1u << 1,   /**< writable by SDO (and RPDO when mapped) */
    CO_F_PERSIST = 1u << 2, /**< saved by 0x1010 and loaded at boot */
    CO_F_RUNTIME = 1u << 3, /**< may change while the drive runs */
    CO_F_PDO = 1u << 4,     /**< may be mapped into a PDO */
    CO_F_LIMITS = 1u << 5,  /**< min/max are checked on write */
};

/** Where an entry's value lives. */
typedef enum {
    CO_BIND_CONST = 0,  /**< constant: def (numbers) or str (strings) */
    CO_BIND_NODEID = 1, /**< constant def + the active node id (COB-IDs) */
    CO_BIND_CFG = 2,    /**< ctl_cfg member at offset (written via drive_cfg_edit/commit) */
    CO_BIND_COMM = 3,   /**< co_comm_cfg member at offset (the drive's d->co.comm) */
    CO_BIND_SCOPE = 4,  /**< scope_cfg member at offset (the drive's d->scope.cfg) */
    CO_BIND_SNAP = 5,   /**< drive_snapshot member at offset (the background copy) */
    CO_BIND_DRIVE = 6,  /**< drive member at offset (read only) */
    CO_BIND_FN = 7,     /**< handled by co_fn_read/co_fn_write; offset is a co_fn_id */
} co_bind;

/** Kind of the bound C field (its size is csize bytes). */
typedef enum {
    CO_CK_FLOAT = 0, /**< float */
    CO_CK_UINT = 1,  /**< unsigned integer or enum of csize bytes */
    CO_CK_SINT = 2,  /**< signed integer of csize bytes */
    CO_CK_BOOL = 3,  /**< bool */
    CO_CK_BYTES = 4, /**< string or domain */
} co_ckind;

/** A numeric CAN raw value; which member is valid follows the entry's dtype. */
typedef union {
    float f;
    uint32_t u;
    int32_t i;
} co_num;

/** One object-dictionary entry (generated; see dtc/param_table.h). */
typedef struct co_param {
    const char *name;        /**< unique parameter name (the table's name) */
    uint16_t index;          /**< CANopen index */
    uint8_t sub;             /**< subindex */
    uint8_t dtype;           /**< co_dtype */
    uint8_t flags;           /**< co_flag bits */
    uint8_t bind;            /**< co_bind */
    uint8_t ckind;           /**< co_ckind of the bound field */
    uint8_t csize;           /**< size of the bound field, bytes */
    uint16_t offset;         /**< offsetof in the bound struct, or co_fn_id */
    float k;                 /**< CAN raw units per internal unit (1 for integers bound to integers) */
    co_num min, max, def;    /**< limits (if CO_F_LIMITS) and default, CAN raw */
    const uint32_t *allowed; /**< optional set of allowed raw values (NULL: any in range) */
    uint8_t n_allowed;       /**< entries in allowed */
    const char *str;         /**< value of a constant string */
} co_param;

/** Length in bytes (1, 2 or 4) of a numeric data type on the bus (0 for strings and domains). Context: ANY. */
size_t co_dtype_size(uint8_t dtype);

/**
 * Find the entry at (@p index, @p sub).
 * @param[out] abort CO_ABORT_NO_OBJECT when no entry has that index,
 *             CO_ABORT_NO_SUB when the index exists but not the subindex.
 * @return the entry or NULL. Context: BG.
 */
const co_param *co_od_find(uint16_t index, uint8_t sub, uint32_t *abort);

/** Find an entry by its parameter name, or NULL. Context: BG. */
const co_param *co_od_find_name(const char *name);

/**
 * Read a numeric entry as its CAN raw value (scaled, rounded and saturated
 * to the data type). Telemetry entries read the background copy
 * d->bg_snap. @return CO_ABORT_NONE or an abort code. Context: BG.
 */
uint32_t co_od_read_num(struct drive *d, const co_param *p, co_num *out);

/**
 * Read any non-domain entry as bus bytes (little-endian numbers, strings
 * without terminator) into @p buf of @p cap bytes.
 * @param[out] len bytes written. @return CO_ABORT_NONE or an abort code. Context: BG.
 */
uint32_t co_od_read(struct drive *d, const co_param *p, uint8_t *buf, size_t cap, size_t *len);

/** Write origins: they differ only in which checks apply. */
typedef enum {
    CO_WR_SDO = 0,  /**< a client's SDO download: every check */
    CO_WR_PDO = 1,  /**< an RPDO: every check */
    CO_WR_LOAD = 2, /**< the persisted set or defaults at boot: access and state not checked */
} co_wr_origin;

/**
 * Decode and check bus bytes for @p p without applying them: length,
 * access (unless CO_WR_LOAD), NaN, range, allowed set.
 * @param[out] v the decoded raw value. @return CO_ABORT_NONE or an abort code.
 * Context: BG.
 */
uint32_t co_od_check(const co_param *p, const uint8_t *data, size_t len, co_wr_origin origin, co_num *v);

/**
 * Decode, check and apply a write of @p len bytes. Configuration entries are
 * applied with one drive_cfg_edit()/drive_cfg_commit() pair after the
 * cross-field check (ctl_cfg_check) passed. Entries without CO_F_RUNTIME
 * are refused with CO_ABORT_STATE while the drive runs (co_od_running).
 * @return CO_ABORT_NONE (applied) or an abort code (nothing changed). Context: BG.
 */
uint32_t co_od_write(struct drive *d, const co_param *p, const uint8_t *data, size_t len, co_wr_origin origin);

/**
 * Apply an already checked raw value to @p p; configuration entries go into
 * @p edit (a copy from drive_cfg_edit) which the caller commits. Used for
 * batches (load, restore defaults). Context: BG.
 */
void co_od_apply(struct drive *d, const co_param *p, const co_num *v, ctl_cfg *edit);

/** @return true while the drive is commanded to run or is magnetising/running. Context: BG. */
bool co_od_running(const struct drive *d);

/** Encode a raw value of @p dtype little-endian into @p buf (co_dtype_size bytes). Context: ANY. */
void co_num_encode(uint8_t dtype, const co_num *v, uint8_t *buf);

/** Decode @p dtype little-endian bytes (co_dtype_size of them); short signed types are sign-extended. Context: ANY. */
co_num co_num_decode(uint8_t dtype, const uint8_t *buf);

#ifdef __cplusplus
}
#endif

#endif /* DTC_CANOPEN_CO_OD_H */
