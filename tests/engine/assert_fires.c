/* An assert fires where asserts are compiled in (this test and Debug/sanitizer builds): a child
 * breaks a contract and must die of SIGABRT, not go on. Built with NDEBUG undefined whatever the
 * build type. Two contracts:
 * - aa_rng_below(r, 0): n > 0 (with NDEBUG it divides by zero: SIGFPE);
 * - ASSERT_LOCK_HELD (server/lock_held.h, the _locked functions' precondition) on a mutex
 *   nobody holds. */
#include <pthread.h>
#include <signal.h>
#include <stdio.h>
#include <sys/wait.h>
#include <unistd.h>

#include "lock_held.h"
#include "rng.h"

static void rng_below_zero(void)
{
    aa_rng r;
    aa_rng_seed(&r, 1, 1);
    volatile uint32_t zero = 0;
    aa_rng_below(&r, zero);
}

static void lock_not_held(void)
{
    pthread_mutex_t m = PTHREAD_MUTEX_INITIALIZER;
    ASSERT_LOCK_HELD(&m);
}

static int aborts(const char *what, void (*broken)(void))
{
    pid_t pid = fork();
    if (pid < 0)
        return 2;
    if (pid == 0) {
        /* The assert's message on stderr is expected; keep the test output clean. */
        freopen("/dev/null", "w", stderr);
        broken();
        _exit(0); /* the contract was not checked */
    }
    int status = 0;
    if (waitpid(pid, &status, 0) != pid)
        return 2;
    if (WIFSIGNALED(status) && WTERMSIG(status) == SIGABRT) {
        printf("%s aborted on its assert\n", what);
        return 0;
    }
    printf("%s: expected SIGABRT, got %s %d\n", what, WIFSIGNALED(status) ? "signal" : "exit",
           WIFSIGNALED(status) ? WTERMSIG(status) : WEXITSTATUS(status));
    return 1;
}

int main(void)
{
    int rc = aborts("aa_rng_below(r, 0)", rng_below_zero);
    int rc2 = aborts("ASSERT_LOCK_HELD on a free mutex", lock_not_held);
    return rc ? rc : rc2;
}
