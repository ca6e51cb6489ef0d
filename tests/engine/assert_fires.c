/* An assert fires where asserts are compiled in (this test and Debug/sanitizer builds): a
 * child breaks aa_rng_below's contract (n > 0) and must die of SIGABRT, not divide by zero
 * (SIGFPE) or return. Built with NDEBUG undefined whatever the build type. */
#include <signal.h>
#include <stdio.h>
#include <sys/wait.h>
#include <unistd.h>

#include "rng.h"

int main(void)
{
    pid_t pid = fork();
    if (pid < 0)
        return 2;
    if (pid == 0) {
        /* The assert's message on stderr is expected; keep the test output clean. */
        freopen("/dev/null", "w", stderr);
        aa_rng r;
        aa_rng_seed(&r, 1, 1);
        volatile uint32_t zero = 0;
        aa_rng_below(&r, zero);
        _exit(0); /* the contract was not checked */
    }
    int status = 0;
    if (waitpid(pid, &status, 0) != pid)
        return 2;
    if (WIFSIGNALED(status) && WTERMSIG(status) == SIGABRT) {
        printf("aa_rng_below(r, 0) aborted on its assert\n");
        return 0;
    }
    printf("expected SIGABRT, got %s %d\n", WIFSIGNALED(status) ? "signal" : "exit",
           WIFSIGNALED(status) ? WTERMSIG(status) : WEXITSTATUS(status));
    return 1;
}
