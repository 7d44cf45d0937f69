/**
 * @file co_od.h
 * @brief The CANopen object dictionary: typed entries generated from the one
 *        parameter table (tools/params/parameters.toml), and the checked
 *        read/write path every SDO, PDO and persisted value goes through.
 *
 * Every entry binds a CANopen object (index, subindex, CiA 301 data type) to
 * a value: a constant, the node id, a communication setting of the device
 * (co_comm_cfg), or something of the application's (bind >= CO_BIND_APP),
 * which the device reaches only through the application's read and write
 * hooks (co_app.h). Values on the bus are "CAN raw" values: raw = internal *
 * k (k from the table's scale and resolution, e.g. rpm per rad/s); limits
 * and defaults are stored raw.
 *
 * A write is decoded, checked here (length, access, NaN, range, allowed set,
 * device state) and only then handed to the application, which may still
 * refuse it (cross-field consistency); a refused request changes nothing.
 *
 * Context: everything here is background (BG) only.
 */
#ifndef DTC_CANOPEN_CO_OD_H
#define DTC_CANOPEN_CO_OD_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>


#ifdef __cplusplus
extern "C" {
#endif

struct co_dev;

/* ---------------------------------------------------- CiA 301 abort codes */
#define CO_ABORT_NONE 0x00000000u
#define CO_ABORT_TOGGLE 0x05030000u          /**< toggle bit not alternated */
#define CO_ABORT_TIMEOUT 0x05040000u         /**< SDO protocol timed out */
#define CO_ABORT_CMD 0x05040001u             /**< command specifier not valid or unknown */
#define CO_ABORT_BLKSIZE 0x05040002u         /**< invalid block size (block mode) */
#define CO_ABORT_SEQNO 0x05040003u           /**< invalid sequence number (block mode) */
#define CO_ABORT_CRC 0x05040004u             /**< CRC error (block mode) */
#define CO_ABORT_WRITE_ONLY 0x06010001u      /**< attempt to read a write-only object */
#define CO_ABORT_READ_ONLY 0x06010002u       /**< attempt to write a read-only object */
#define CO_ABORT_NO_OBJECT 0x06020000u       /**< object does not exist */
#define CO_ABORT_PARAM_INCOMPAT 0x06040043u  /**< general parameter incompatibility */
#define CO_ABORT_LENGTH 0x06070010u          /**< data type does not match, length mismatch */
#define CO_ABORT_NO_SUB 0x06090011u          /**< subindex does not exist */
#define CO_ABORT_INVALID_VALUE 0x06090030u   /**< invalid value (NaN, not in the allowed set) */
#define CO_ABORT_VALUE_HIGH 0x06090031u      /**< value too high */
#define CO_ABORT_VALUE_LOW 0x06090032u       /**< value too low */
#define CO_ABORT_MAX_BELOW_MIN 0x06090036u   /**< maximum value is less than minimum value */
#define CO_ABORT_GENERAL 0x08000000u         /**< general error */
#define CO_ABORT_STORE 0x08000020u           /**< cannot be stored (wrong signature, NVM failure) */
#define CO_ABORT_STATE 0x08000022u           /**< refused in the present device state (running) */

/** The CiA 301 data types an entry may have (the numbers are the EDS DataType codes). */
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
    CO_F_RUNTIME = 1u << 3, /**< may change while the machine runs (co_app.running) */
    CO_F_PDO = 1u << 4,     /**< may be mapped into a PDO */
    CO_F_LIMITS = 1u << 5,  /**< min/max are checked on write */
};

/** Where an entry's value lives. */
typedef enum {
    CO_BIND_CONST = 0,  /**< constant: def (numbers) or str (strings) */
    CO_BIND_NODEID = 1, /**< constant def + the active node id (COB-IDs) */
    CO_BIND_COMM = 2,   /**< co_comm_cfg member at offset (the device's own settings) */
    CO_BIND_ERRHIST = 3, /**< the device's error history 0x1003 (co_emcy.h): sub 0 the count (writing 0 clears), sub k the k-th newest */
    CO_BIND_APP = 8,    /**< this and above: the application's (read and written through co_app hooks) */
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

/** One object-dictionary entry (the application's table, e.g. generated). */
typedef struct co_param {
    const char *name;        /**< unique parameter name (the table's name) */
    uint16_t index;          /**< CANopen index */
    uint8_t sub;             /**< subindex */
    uint8_t dtype;           /**< co_dtype */
    uint8_t flags;           /**< co_flag bits */
    uint8_t bind;            /**< co_bind */
    uint8_t ckind;           /**< co_ckind of the bound field */
    uint8_t csize;           /**< size of the bound field, bytes */
    uint16_t offset;         /**< offsetof in the bound struct, or an application handler id */
    float k;                 /**< CAN raw units per internal unit (1 for integers bound to integers) */
    co_num min, max, def;    /**< limits (if CO_F_LIMITS) and default, CAN raw */
    const uint32_t *allowed; /**< optional set of allowed raw values (NULL: any in range) */
    uint8_t n_allowed;       /**< entries in allowed */
    const char *str;         /**< value of a constant string */
    float max_step;          /**< while the machine runs, a write may change the value by at most this
                                  fraction of its present magnitude (0: any change; needs CO_F_RUNTIME) */
} co_param;

/** The entries of a dictionary, sorted by (index, subindex). */
typedef struct {
    const co_param *params;
    uint16_t count;
} co_dict;

/** Length in bytes (1, 2 or 4) of a numeric data type on the bus (0 for strings and domains). Context: ANY. */
size_t co_dtype_size(uint8_t dtype);

/**
 * Find the entry at (@p index, @p sub) in @p od.
 * @param[out] abort CO_ABORT_NO_OBJECT when no entry has that index,
 *             CO_ABORT_NO_SUB when the index exists but not the subindex.
 * @return the entry or NULL. Context: BG.
 */
const co_param *co_od_find(const co_dict *od, uint16_t index, uint8_t sub, uint32_t *abort);

/** Find an entry by its parameter name, or NULL. Context: BG. */
const co_param *co_od_find_name(const co_dict *od, const char *name);

/**
 * Read a numeric entry as its CAN raw value (scaled, rounded and saturated
 * to the data type). Application entries are read through the read hook.
 * @return CO_ABORT_NONE or an abort code. Context: BG.
 */
uint32_t co_od_read_num(struct co_dev *c, const co_param *p, co_num *out);

/**
 * Read any non-domain entry as bus bytes (little-endian numbers, strings
 * without terminator) into @p buf of @p cap bytes.
 * @param[out] len bytes written. @return CO_ABORT_NONE or an abort code. Context: BG.
 */
uint32_t co_od_read(struct co_dev *c, const co_param *p, uint8_t *buf, size_t cap, size_t *len);

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
 * Decode, check and apply a write of @p len bytes. While the application says
 * it runs, entries without CO_F_RUNTIME are refused with CO_ABORT_STATE, and
 * so is a change larger than max_step x |present value| (a gain moves in
 * bounded steps while running). Application entries are applied by its write
 * hook, which may refuse.
 * @return CO_ABORT_NONE (applied) or an abort code (nothing changed). Context: BG.
 */
uint32_t co_od_write(struct co_dev *c, const co_param *p, const uint8_t *data, size_t len, co_wr_origin origin);

/** A checked bus raw value in the entry's internal unit (raw / k for floats). Context: ANY. */
co_num co_od_to_internal(const co_param *p, const co_num *raw);

/** An internal value as the bus raw value: scaled by k, rounded, saturated (NaN reads 0). Context: ANY. */
co_num co_od_to_raw(const co_param *p, co_num internal);

/** The internal value of the C field of @p p at @p base + p->offset (by ckind and csize). Context: ANY. */
co_num co_field_get(const void *base, const co_param *p);

/** Store an internal value into the C field of @p p at @p base + p->offset. Context: BG. */
void co_field_set(void *base, const co_param *p, const co_num *internal);

/** Encode a raw value of @p dtype little-endian into @p buf (co_dtype_size bytes). Context: ANY. */
void co_num_encode(uint8_t dtype, const co_num *v, uint8_t *buf);

/** Decode @p dtype little-endian bytes (co_dtype_size of them); short signed types are sign-extended. Context: ANY. */
co_num co_num_decode(uint8_t dtype, const uint8_t *buf);

#ifdef __cplusplus
}
#endif

#endif /* DTC_CANOPEN_CO_OD_H */
