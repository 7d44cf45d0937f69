/**
 * @file file_safety.c
 * @brief Output paths dtc-sim may write (see sim/file_safety.h).
 */
#define _POSIX_C_SOURCE 200809L
#include "sim/file_safety.h"

#include <errno.h>
#include <stdio.h>
#include <string.h>
#include <sys/stat.h>

static bool same_file(const struct stat *a, const char *path)
{
    struct stat b;
    return path != NULL && stat(path, &b) == 0 && a->st_dev == b.st_dev && a->st_ino == b.st_ino;
}

bool sim_output_allowed(const char *what, const char *path, const char *input, const char *other, char *err,
                        size_t errlen)
{
    struct stat st;
    if (stat(path, &st) != 0) {
        if (errno == ENOENT)
            return true; /* a new file */
        snprintf(err, errlen, "%s %s: %s", what, path, strerror(errno));
        return false;
    }
    if (!S_ISREG(st.st_mode)) {
        snprintf(err, errlen, "%s %s: not a regular file (a directory, device or FIFO is never replaced)", what,
                 path);
        return false;
    }
    if (same_file(&st, input)) {
        snprintf(err, errlen, "%s %s: is the scenario file itself", what, path);
        return false;
    }
    if (same_file(&st, other)) {
        snprintf(err, errlen, "%s %s: is the same file as another output", what, path);
        return false;
    }
    return true;
}
