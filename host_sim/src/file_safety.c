/**
 * @file file_safety.c
 * @brief The outputs dtc-sim may write (see sim/file_safety.h).
 */
#define _XOPEN_SOURCE 700 /* realpath */
#include "sim/file_safety.h"

#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

/* What a name refers to, for telling whether two names are one file. */
typedef struct {
    const char *what;   /* the option; NULL for the input */
    const char *path;   /* the name (for a temporary: its own name) */
    const char *output; /* for a temporary: the output it belongs to; else NULL */
    bool listed;        /* a directory entry exists under the name (lstat) */
    bool has_inode;     /* it resolves to a file: dev and ino are valid */
    dev_t dev;
    ino_t ino;
    char *resolved;     /* the folder's real path + "/" + the name (or the real path); NULL: unknown */
} name_id;

/* Split @p path into a freshly allocated folder ("." when none) and its last part. */
static char *folder_of(const char *path, const char **base)
{
    const char *slash = strrchr(path, '/');
    if (slash == NULL) {
        *base = path;
        return strdup(".");
    }
    *base = slash + 1;
    if (slash == path)
        return strdup("/");
    size_t n = (size_t)(slash - path);
    char *dir = malloc(n + 1u);
    if (dir != NULL) {
        memcpy(dir, path, n);
        dir[n] = '\0';
    }
    return dir;
}

static char *resolve(const char *path, bool exists)
{
    if (exists) {
        char *r = realpath(path, NULL);
        if (r != NULL)
            return r;
    }
    const char *base;
    char *dir = folder_of(path, &base);
    if (dir == NULL)
        return NULL;
    char *real_dir = realpath(dir, NULL);
    free(dir);
    if (real_dir == NULL)
        return NULL;
    size_t n = strlen(real_dir) + 1u + strlen(base) + 1u;
    char *r = malloc(n);
    if (r != NULL)
        snprintf(r, n, "%s/%s", real_dir, base);
    free(real_dir);
    return r;
}

static void identify(name_id *id)
{
    struct stat st;
    id->listed = lstat(id->path, &st) == 0;
    id->has_inode = stat(id->path, &st) == 0;
    if (id->has_inode) {
        id->dev = st.st_dev;
        id->ino = st.st_ino;
    }
    id->resolved = resolve(id->path, id->has_inode);
}

static bool same_file(const name_id *a, const name_id *b)
{
    if (a->has_inode && b->has_inode && a->dev == b->dev && a->ino == b->ino)
        return true;
    return a->resolved != NULL && b->resolved != NULL && strcmp(a->resolved, b->resolved) == 0;
}

/* An output's own name: a new name in a folder we may write, or a regular file. */
static bool output_name_ok(const sim_output *o, char *err, size_t errlen)
{
    size_t len = strlen(o->path);
    if (len == 0u || o->path[len - 1u] == '/') {
        snprintf(err, errlen, "%s '%s': not a file name", o->what, o->path);
        return false;
    }
    struct stat st;
    if (lstat(o->path, &st) == 0) {
        if (S_ISLNK(st.st_mode) && stat(o->path, &st) != 0) {
            snprintf(err, errlen, "%s %s: a dangling symbolic link (never replaced)", o->what, o->path);
            return false;
        }
        if (!S_ISREG(st.st_mode)) {
            snprintf(err, errlen, "%s %s: not a regular file (a directory, device or FIFO is never replaced)",
                     o->what, o->path);
            return false;
        }
    } else if (errno != ENOENT) {
        snprintf(err, errlen, "%s %s: %s", o->what, o->path, strerror(errno));
        return false;
    }
    /* The temporary is created in the output's folder and renamed over it. */
    const char *base;
    char *dir = folder_of(o->path, &base);
    if (dir == NULL) {
        snprintf(err, errlen, "%s %s: out of memory", o->what, o->path);
        return false;
    }
    int e = 0;
    if (stat(dir, &st) != 0)
        e = errno;
    else if (!S_ISDIR(st.st_mode))
        e = ENOTDIR;
    else if (access(dir, W_OK | X_OK) != 0)
        e = errno;
    free(dir);
    if (e != 0) {
        snprintf(err, errlen, "%s %s: cannot create: %s", o->what, o->path, strerror(e));
        return false;
    }
    return true;
}

/* The message for two names of one file, @p a listed before @p b. */
static void explain_same(const name_id *a, const name_id *b, char *err, size_t errlen)
{
    if (a->what == NULL) { /* the input */
        if (b->output == NULL)
            snprintf(err, errlen, "%s %s: is the scenario file itself", b->what, b->path);
        else
            snprintf(err, errlen, "%s %s: its temporary file %s is the scenario file itself", b->what, b->output,
                     b->path);
    } else if (a->output == NULL && b->output == NULL) {
        snprintf(err, errlen, "%s %s: is the same file as %s %s", b->what, b->path, a->what, a->path);
    } else if (a->output == NULL) {
        snprintf(err, errlen, "%s %s: is the temporary file of %s %s", a->what, a->path, b->what, b->output);
    } else if (b->output == NULL) {
        snprintf(err, errlen, "%s %s: is the temporary file of %s %s", b->what, b->path, a->what, a->output);
    } else {
        snprintf(err, errlen, "%s %s: its temporary file %s is the same file as the temporary file %s of %s %s",
                 b->what, b->output, b->path, a->path, a->what, a->output);
    }
}

bool sim_outputs_allowed(const char *input, const sim_output *out, size_t n, char *err, size_t errlen)
{
    for (size_t i = 0; i < n; i++)
        if (out[i].path != NULL && !output_name_ok(&out[i], err, errlen))
            return false;

    /* The names in the order their clashes are reported: the input, the
     * outputs, then the temporaries. */
    name_id *ids = calloc(2u * n + 1u, sizeof *ids);
    char **temps = calloc(n + 1u, sizeof *temps);
    bool ok = ids != NULL && temps != NULL;
    size_t count = 0;
    if (ok && input != NULL)
        ids[count++] = (name_id){ .path = input };
    for (size_t i = 0; ok && i < n; i++)
        if (out[i].path != NULL)
            ids[count++] = (name_id){ .what = out[i].what, .path = out[i].path };
    for (size_t i = 0; ok && i < n; i++) {
        if (out[i].path == NULL)
            continue;
        size_t len = strlen(out[i].path) + strlen(out[i].temp_suffix) + 1u;
        temps[i] = malloc(len);
        if (temps[i] == NULL) {
            ok = false;
            break;
        }
        snprintf(temps[i], len, "%s%s", out[i].path, out[i].temp_suffix);
        ids[count++] = (name_id){ .what = out[i].what, .path = temps[i], .output = out[i].path };
    }
    if (!ok)
        snprintf(err, errlen, "out of memory");
    for (size_t i = 0; ok && i < count; i++)
        identify(&ids[i]);

    for (size_t i = 0; ok && i < count; i++)
        for (size_t j = i + 1u; ok && j < count; j++)
            if (same_file(&ids[i], &ids[j])) {
                explain_same(&ids[i], &ids[j], err, errlen);
                ok = false;
            }
    for (size_t i = 0; ok && i < count; i++)
        if (ids[i].output != NULL && ids[i].listed) {
            snprintf(err, errlen,
                     "%s %s: its temporary file %s exists (left by an interrupted run?); dtc-sim never "
                     "overwrites a file it did not create: remove it first",
                     ids[i].what, ids[i].output, ids[i].path);
            ok = false;
        }

    for (size_t i = 0; ids != NULL && i < count; i++)
        free(ids[i].resolved);
    for (size_t i = 0; temps != NULL && i < n; i++)
        free(temps[i]);
    free(ids);
    free(temps);
    return ok;
}
