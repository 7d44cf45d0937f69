/**
 * @file co_od.c
 * @brief Object dictionary: lookup, conversion between bus (raw) and C
 *        (internal) values, and the checked write path.
 */
#include "dtc/canopen/co_od.h"

#include <string.h>

#include "dtc/canopen/co_dev.h"

size_t co_dtype_size(uint8_t dtype)
{
    switch (dtype) {
    case CO_DT_BOOLEAN:
    case CO_DT_INTEGER8:
    case CO_DT_UNSIGNED8:
        return 1u;
    case CO_DT_INTEGER16:
    case CO_DT_UNSIGNED16:
        return 2u;
    case CO_DT_INTEGER32:
    case CO_DT_UNSIGNED32:
    case CO_DT_REAL32:
        return 4u;
    default:
        return 0u;
    }
}

static uint32_t key_of(uint16_t index, uint8_t sub) { return ((uint32_t)index << 8) | sub; }

const co_param *co_od_find(const co_dict *od, uint16_t index, uint8_t sub, uint32_t *abort)
{
    /* The table is sorted by (index, sub): binary search for the key, and
     * remember whether the index exists at all for the right abort code. */
    uint32_t key = key_of(index, sub);
    const co_param *params = od->params;
    uint32_t lo = 0u, hi = od->count;
    bool index_seen = false;
    while (lo < hi) {
        uint32_t mid = lo + (hi - lo) / 2u;
        const co_param *p = &params[mid];
        uint32_t k = key_of(p->index, p->sub);
        if (p->index == index)
            index_seen = true;
        if (k == key) {
            if (abort != NULL)
                *abort = CO_ABORT_NONE;
            return p;
        }
        if (k < key)
            lo = mid + 1u;
        else
            hi = mid;
    }
    if (!index_seen) {
        /* The search may have skipped the index's entries: look at the
         * neighbours of the insertion point. */
        if (lo < od->count && params[lo].index == index)
            index_seen = true;
        if (lo > 0u && params[lo - 1u].index == index)
            index_seen = true;
    }
    if (abort != NULL)
        *abort = index_seen ? CO_ABORT_NO_SUB : CO_ABORT_NO_OBJECT;
    return NULL;
}

const co_param *co_od_find_name(const co_dict *od, const char *name)
{
    if (name == NULL)
        return NULL;
    for (uint32_t i = 0u; i < od->count; i++)
        if (strcmp(od->params[i].name, name) == 0)
            return &od->params[i];
    return NULL;
}

/* The low @p size bytes (1, 2 or 4) of an integer field, zero-extended. */
static uint32_t field_bits(const uint8_t *ptr, uint8_t size)
{
    if (size == 1u)
        return ptr[0];
    if (size == 2u) {
        uint16_t x;
        memcpy(&x, ptr, 2u);
        return x;
    }
    uint32_t x;
    memcpy(&x, ptr, 4u);
    return x;
}

/* Sign-extend the low @p size bytes (1, 2 or 4) of @p u. */
static int32_t sign_extend(uint32_t u, size_t size)
{
    if (size == 1u)
        return (int32_t)(int8_t)(uint8_t)u;
    if (size == 2u)
        return (int32_t)(int16_t)(uint16_t)u;
    return (int32_t)u;
}

/* ------------------------------------------------------------- encoding */

void co_num_encode(uint8_t dtype, const co_num *v, uint8_t *buf)
{
    uint32_t u = v->u; /* same bits for f, u and i */
    size_t n = co_dtype_size(dtype);
    for (size_t i = 0u; i < n; i++)
        buf[i] = (uint8_t)(u >> (8u * i));
}

co_num co_num_decode(uint8_t dtype, const uint8_t *buf)
{
    co_num v;
    uint32_t u = 0u;
    size_t n = co_dtype_size(dtype);
    for (size_t i = 0u; i < n; i++)
        u |= (uint32_t)buf[i] << (8u * i);
    v.u = u;
    /* Sign-extend the short signed types so v.i holds the value. */
    if (dtype == CO_DT_INTEGER8 || dtype == CO_DT_INTEGER16)
        v.i = sign_extend(u, n);
    return v;
}

/* ------------------------------------------------------- bound C fields */

co_num co_field_get(const void *base, const co_param *p)
{
    const uint8_t *ptr = (const uint8_t *)base + p->offset;
    co_num v;
    v.u = 0u;
    switch (p->ckind) {
    case CO_CK_FLOAT:
        memcpy(&v.f, ptr, sizeof v.f);
        break;
    case CO_CK_BOOL:
        v.u = ptr[0] != 0u ? 1u : 0u;
        break;
    case CO_CK_UINT:
        v.u = field_bits(ptr, p->csize);
        break;
    case CO_CK_SINT:
        v.i = sign_extend(field_bits(ptr, p->csize), p->csize);
        break;
    default:
        break;
    }
    return v;
}

void co_field_set(void *base, const co_param *p, const co_num *v)
{
    uint8_t *ptr = (uint8_t *)base + p->offset;
    switch (p->ckind) {
    case CO_CK_FLOAT:
        memcpy(ptr, &v->f, sizeof v->f);
        break;
    case CO_CK_BOOL: {
        bool b = v->u != 0u;
        memcpy(ptr, &b, sizeof b);
        break;
    }
    case CO_CK_UINT:
    case CO_CK_SINT:
        if (p->csize == 1u) {
            ptr[0] = (uint8_t)v->u;
        } else if (p->csize == 2u) {
            uint16_t x = (uint16_t)v->u;
            memcpy(ptr, &x, 2u);
        } else {
            memcpy(ptr, &v->u, 4u);
        }
        break;
    default:
        break;
    }
}

/* ------------------------------------------------ raw <-> internal values */

static bool dtype_signed(uint8_t dt)
{
    return dt == CO_DT_INTEGER8 || dt == CO_DT_INTEGER16 || dt == CO_DT_INTEGER32;
}

/* Range of an integer bus type, as floats for saturating a scaled value. */
static void dtype_range_f(uint8_t dt, float *lo, float *hi)
{
    switch (dt) {
    case CO_DT_INTEGER8: *lo = -128.0f; *hi = 127.0f; break;
    case CO_DT_INTEGER16: *lo = -32768.0f; *hi = 32767.0f; break;
    case CO_DT_INTEGER32: *lo = -2147483648.0f; *hi = 2147483520.0f; break; /* largest float below 2^31 */
    case CO_DT_UNSIGNED8: case CO_DT_BOOLEAN: *lo = 0.0f; *hi = 255.0f; break;
    case CO_DT_UNSIGNED16: *lo = 0.0f; *hi = 65535.0f; break;
    default: *lo = 0.0f; *hi = 4294967040.0f; break; /* largest float below 2^32 */
    }
}

/* Truncate or saturate an integer to the bus type: unsigned types keep the
 * low bits (fault words, wrapping counters), signed types saturate. */
static co_num int_to_dtype(uint8_t dt, int64_t x)
{
    co_num v;
    switch (dt) {
    case CO_DT_INTEGER8: v.i = (int32_t)(x < -128 ? -128 : (x > 127 ? 127 : x)); break;
    case CO_DT_INTEGER16: v.i = (int32_t)(x < -32768 ? -32768 : (x > 32767 ? 32767 : x)); break;
    case CO_DT_INTEGER32:
        v.i = (int32_t)(x < INT32_MIN ? INT32_MIN : (x > INT32_MAX ? INT32_MAX : x));
        break;
    case CO_DT_BOOLEAN: v.u = x != 0 ? 1u : 0u; break;
    case CO_DT_UNSIGNED8: v.u = (uint32_t)x & 0xFFu; break;
    case CO_DT_UNSIGNED16: v.u = (uint32_t)x & 0xFFFFu; break;
    default: v.u = (uint32_t)x; break;
    }
    return v;
}

/* Internal value -> bus raw value: scale by k, round half away from zero,
 * saturate to the type (NaN reads as 0). */
co_num co_od_to_raw(const co_param *p, co_num in)
{
    co_num out;
    if (p->dtype == CO_DT_REAL32) {
        out.f = (p->ckind == CO_CK_FLOAT ? in.f : (float)in.u) * p->k;
        return out;
    }
    if (p->ckind == CO_CK_FLOAT) {
        float x = in.f * p->k;
        float lo, hi;
        dtype_range_f(p->dtype, &lo, &hi);
        if (!(x == x)) /* NaN */
            x = 0.0f;
        x = x >= 0.0f ? x + 0.5f : x - 0.5f;
        x = x < lo ? lo : (x > hi ? hi : x);
        if (dtype_signed(p->dtype))
            return int_to_dtype(p->dtype, (int64_t)(int32_t)x);
        return int_to_dtype(p->dtype, (int64_t)(uint32_t)x);
    }
    if (p->ckind == CO_CK_SINT)
        return int_to_dtype(p->dtype, (int64_t)in.i);
    return int_to_dtype(p->dtype, (int64_t)in.u);
}

/* Checked bus raw value -> internal value. */
co_num co_od_to_internal(const co_param *p, const co_num *raw)
{
    co_num out;
    if (p->ckind != CO_CK_FLOAT) {
        out = *raw; /* integers bound to integers are never scaled */
        return out;
    }
    float x;
    if (p->dtype == CO_DT_REAL32)
        x = raw->f;
    else if (dtype_signed(p->dtype))
        x = (float)raw->i;
    else
        x = (float)raw->u;
    out.f = p->k != 1.0f ? x / p->k : x;
    return out;
}

/* ---------------------------------------------------------------- reads */

uint32_t co_od_read_num(co_dev *c, const co_param *p, co_num *out)
{
    if (co_dtype_size(p->dtype) == 0u)
        return CO_ABORT_LENGTH;
    switch (p->bind) {
    case CO_BIND_CONST:
        *out = p->def;
        return CO_ABORT_NONE;
    case CO_BIND_NODEID:
        out->u = p->def.u + c->node_id;
        return CO_ABORT_NONE;
    case CO_BIND_COMM:
        *out = co_od_to_raw(p, co_field_get(&c->comm, p));
        return CO_ABORT_NONE;
    case CO_BIND_ERRHIST:
        return co_err_history_read(&c->err_history, p->sub, &out->u);
    default: {
        if (p->bind < CO_BIND_APP)
            return CO_ABORT_GENERAL;
        co_num in;
        uint32_t rc = c->app->read(c->app->ctx, p, &in);
        if (rc == CO_ABORT_NONE)
            *out = co_od_to_raw(p, in);
        return rc;
    }
    }
}

uint32_t co_od_read(co_dev *c, const co_param *p, uint8_t *buf, size_t cap, size_t *len)
{
    *len = 0u;
    if ((p->flags & CO_F_READ) == 0u)
        return CO_ABORT_WRITE_ONLY;
    if (p->dtype == CO_DT_VISIBLE_STRING) {
        size_t n = p->str != NULL ? strlen(p->str) : 0u;
        if (n > cap)
            return CO_ABORT_GENERAL;
        memcpy(buf, p->str, n);
        *len = n;
        return CO_ABORT_NONE;
    }
    size_t n = co_dtype_size(p->dtype);
    if (n == 0u || n > cap)
        return CO_ABORT_GENERAL; /* domains are streamed by the SDO server */
    co_num v;
    uint32_t rc = co_od_read_num(c, p, &v);
    if (rc != CO_ABORT_NONE)
        return rc;
    co_num_encode(p->dtype, &v, buf);
    *len = n;
    return CO_ABORT_NONE;
}

/* --------------------------------------------------------------- writes */

uint32_t co_od_check(const co_param *p, const uint8_t *data, size_t len, co_wr_origin origin, co_num *v)
{
    if (origin != CO_WR_LOAD && (p->flags & CO_F_WRITE) == 0u)
        return CO_ABORT_READ_ONLY;
    size_t n = co_dtype_size(p->dtype);
    if (n == 0u)
        return CO_ABORT_READ_ONLY; /* strings and domains are never written */
    if (len != n)
        return CO_ABORT_LENGTH;
    *v = co_num_decode(p->dtype, data);
    if (p->dtype == CO_DT_REAL32 && !(v->f - v->f == 0.0f)) /* NaN or infinity */
        return CO_ABORT_INVALID_VALUE;
    if (p->dtype == CO_DT_BOOLEAN && v->u > 1u)
        return CO_ABORT_INVALID_VALUE;
    if ((p->flags & CO_F_LIMITS) != 0u) {
        if (p->dtype == CO_DT_REAL32) {
            if (v->f > p->max.f)
                return CO_ABORT_VALUE_HIGH;
            if (v->f < p->min.f)
                return CO_ABORT_VALUE_LOW;
        } else if (dtype_signed(p->dtype)) {
            if (v->i > p->max.i)
                return CO_ABORT_VALUE_HIGH;
            if (v->i < p->min.i)
                return CO_ABORT_VALUE_LOW;
        } else {
            if (v->u > p->max.u)
                return CO_ABORT_VALUE_HIGH;
            if (v->u < p->min.u)
                return CO_ABORT_VALUE_LOW;
        }
    }
    if (p->allowed != NULL) {
        bool ok = false;
        for (uint32_t i = 0u; i < p->n_allowed; i++)
            ok = ok || (p->allowed[i] == v->u);
        if (!ok)
            return CO_ABORT_INVALID_VALUE;
    }
    return CO_ABORT_NONE;
}

/* A running machine takes a new value of @p p only within max_step of the
 * present one (in internal units: floats only, see the table generator). */
static bool within_step(co_dev *c, const co_param *p, const co_num *raw)
{
    co_num cur_raw;
    if (co_od_read_num(c, p, &cur_raw) != CO_ABORT_NONE)
        return false;
    float cur = co_od_to_internal(p, &cur_raw).f;
    float next = co_od_to_internal(p, raw).f;
    float diff = next - cur;
    float mag = cur < 0.0f ? -cur : cur;
    return (diff < 0.0f ? -diff : diff) <= p->max_step * mag;
}

uint32_t co_od_write(co_dev *c, const co_param *p, const uint8_t *data, size_t len, co_wr_origin origin)
{
    co_num v;
    uint32_t rc = co_od_check(p, data, len, origin, &v);
    if (rc != CO_ABORT_NONE)
        return rc;
    if (origin != CO_WR_LOAD && c->app->running(c->app->ctx)) {
        if ((p->flags & CO_F_RUNTIME) == 0u)
            return CO_ABORT_STATE;
        if (p->max_step > 0.0f && !within_step(c, p, &v))
            return CO_ABORT_STATE;
    }
    if (p->bind == CO_BIND_ERRHIST) {
        if (p->sub != 0u)
            return CO_ABORT_READ_ONLY;
        if (v.u != 0u)
            return CO_ABORT_INVALID_VALUE; /* CiA 301: only 0 (clear) may be written */
        co_err_history_clear(&c->err_history);
        return CO_ABORT_NONE;
    }
    co_num in = co_od_to_internal(p, &v);
    if (p->bind == CO_BIND_COMM) {
        co_field_set(&c->comm, p, &in);
        return CO_ABORT_NONE;
    }
    if (p->bind < CO_BIND_APP)
        return CO_ABORT_READ_ONLY; /* constants */
    return c->app->write(c->app->ctx, p, &in);
}
