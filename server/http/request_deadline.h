/* Bounds the time a client may take to deliver one whole request (headers and body).
 *
 * libmicrohttpd's connection timeout is an inactivity timeout: a client trickling one byte a
 * second (slowloris) resets it forever and pins a connection slot. This watchdog tracks every
 * connection (MHD_OPTION_NOTIFY_CONNECTION): a connection is "receiving" from its start, and
 * again after each completed response, until its request has fully arrived. A thread wakes
 * every 250 ms and shuts down the socket of any connection that has been receiving for longer
 * than the deadline; libmicrohttpd then sees the error and cleans up as usual. The CLOSED
 * notification runs before libmicrohttpd closes the fd and takes the same lock, so a shut-down
 * fd is never one that has been reused.
 * The same watchdog bounds the delivery of an answer (--answer-timeout): from the moment a
 * response is queued until it has been sent, however slowly the client reads; an idle timeout
 * alone let 32 readers taking 4 KiB every 10 s hold 4.3 GB of answers for minutes. The time a
 * request spends computing (suspended on the compute pool) counts for neither clock. */
#ifndef AALAB_REQUEST_DEADLINE_H
#define AALAB_REQUEST_DEADLINE_H

#include <microhttpd.h>

typedef struct request_deadline request_deadline;

request_deadline *request_deadline_start(double seconds, double answer_seconds);
void request_deadline_stop(request_deadline *rd);

/* MHD_OPTION_NOTIFY_CONNECTION callback; cls is the request_deadline. */
void request_deadline_notify(void *cls, struct MHD_Connection *conn, void **socket_context,
                             enum MHD_ConnectionNotificationCode code);
/* The clock of a connection just STARTED (socket_context as set by request_deadline_notify)
 * began earlier, at since (CLOCK_MONOTONIC seconds): the time it waited before libmicrohttpd
 * saw it counts. */
void request_deadline_backdate(void *socket_context, double since);
/* The connection's request has fully arrived: stop the clock until its response completes. */
void request_deadline_received(struct MHD_Connection *conn);
/* Its response is queued: the answer's clock runs until request_deadline_completed. */
void request_deadline_sending(struct MHD_Connection *conn);
/* Its response was sent: the clock runs again for the next request on this connection. */
void request_deadline_completed(struct MHD_Connection *conn);

#endif
