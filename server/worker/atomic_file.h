/* Replacing a file atomically, so that a reader on another node never sees half of it: write a
 * temporary file in the same directory, fsync it, rename it over the target, fsync the
 * directory (the rename itself then survives a crash). */
#ifndef AALAB_ATOMIC_FILE_H
#define AALAB_ATOMIC_FILE_H

#include <jansson.h>

#include "aa_core.h"

/* The code of a failed write (the engine's codes have no I/O error). */
#define ATOMIC_EIO (-5)

/* Writes j (compact, reals with 17 significant digits so they read back exactly) to path.
 * ATOMIC_EIO with err naming field (and the system's reason) when it cannot. */
int atomic_write_json(const char *path, const json_t *j, const char *field, aa_error *err);

#endif
