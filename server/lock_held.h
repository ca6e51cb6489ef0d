/* ASSERT_LOCK_HELD(&x->lock) states a function's precondition that it runs with that mutex held:
 * a "_locked" function, or one whose comment says the caller holds the lock. On in Debug and
 * sanitizer builds; NDEBUG (CMake's Release and RelWithDebInfo) compiles it out.
 * A default mutex does not record its owner, so this is the portable weak form of the check:
 * somebody holds it (trylock finds it busy; for the holder too, and nothing changes). A caller
 * that forgot the lock takes it here and the assert aborts, unless another thread holds it at
 * that very moment. */
#ifndef AALAB_LOCK_HELD_H
#define AALAB_LOCK_HELD_H

#include <assert.h>
#include <errno.h>
#include <pthread.h>
#include <stdbool.h>

static inline bool lock_is_held(const pthread_mutex_t *m)
{
    return pthread_mutex_trylock((pthread_mutex_t *)m) == EBUSY; /* const: read-only callers */
}

#define ASSERT_LOCK_HELD(m) assert(lock_is_held(m))

#endif
