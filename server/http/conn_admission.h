/* Admission of accepted connections on one listener, before libmicrohttpd sees them: the peer
 * must be on loopback (TCP), is identified by uid (SO_PEERCRED on the Unix socket, sock_diag on
 * TCP), and is counted against --user-connections per uid and --connection-limit in total. On
 * TCP a connection is also counted against --token-connections by the hash of the Authorization
 * header of its first request (the token is not validated here). Everything counted is given
 * back by conn_admission_release() when the connection closes. Connections are known by fd:
 * an fd is released before it is closed, so it cannot be reused while still registered. */
#ifndef AALAB_CONN_ADMISSION_H
#define AALAB_CONN_ADMISSION_H

#include <stdbool.h>
#include <sys/socket.h>
#include <sys/types.h>

typedef struct conn_peer {
    bool uid_known;
    uid_t uid;
} conn_peer;

typedef enum {
    ADMIT_OK,
    ADMIT_NOT_LOOPBACK, /* TCP peer address outside 127.0.0.0/8 and ::1 */
    ADMIT_USER_LIMIT,   /* the uid already has --user-connections open */
    ADMIT_TOTAL_LIMIT,  /* --connection-limit open in total */
    ADMIT_NO_MEMORY
} conn_admit_result;

typedef struct conn_admission conn_admission;

conn_admission *conn_admission_create(bool is_unix, int total_limit, int user_limit,
                                      int token_limit);
void conn_admission_destroy(conn_admission *ca);
/* Checks and counts fd (peer address sa). On ADMIT_OK the connection is registered. */
conn_admit_result conn_admission_admit(conn_admission *ca, int fd, const struct sockaddr *sa,
                                       socklen_t len, conn_peer *peer);
/* The identity found at admission; false if fd is not registered. */
bool conn_admission_peer(conn_admission *ca, int fd, conn_peer *peer);
/* When fd was admitted (CLOCK_MONOTONIC seconds); false if fd is not registered. */
bool conn_admission_accepted_at(conn_admission *ca, int fd, double *when);
/* Counts fd against a validated token id, once per connection (later calls and an id <= 0, no
 * valid token, are free: such requests are refused 401 by the router). False when that token
 * already has --token-connections open. Counting the id, not the header's text, is what makes
 * the limit hold for "aalab_01_..." and "aalab_1_..." alike (only canonical ids validate). */
bool conn_admission_token(conn_admission *ca, int fd, long long token_id);
/* Gives back what fd holds and forgets it (no-op if not registered). */
void conn_admission_release(conn_admission *ca, int fd);
int conn_admission_open(conn_admission *ca);
int conn_admission_user_limit(const conn_admission *ca);
int conn_admission_token_limit(const conn_admission *ca);
int conn_admission_total_limit(const conn_admission *ca);

#endif
