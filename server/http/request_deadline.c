#define _GNU_SOURCE
#include "request_deadline.h"
#include "aa_core.h"

#include <pthread.h>
#include <stdbool.h>
#include <stdlib.h>
#include <sys/socket.h>
#include <time.h>

typedef struct tracked {
    struct tracked *prev, *next;
    request_deadline *owner;
    int fd;
    double receiving_since; /* monotonic seconds; 0 while the request is being answered */
    double sending_since;   /* its answer was queued then; 0 while none is being sent */
    bool shut;
} tracked;

struct request_deadline {
    pthread_mutex_t lock;
    pthread_cond_t wake;
    pthread_t thread;
    tracked head; /* sentinel of a circular list */
    double seconds, answer_seconds;
    bool stopping;
};

static void *watchdog(void *arg)
{
    request_deadline *rd = arg;
    pthread_mutex_lock(&rd->lock);
    while (!rd->stopping) {
        struct timespec until;
        clock_gettime(CLOCK_REALTIME, &until);
        until.tv_nsec += 250000000L;
        if (until.tv_nsec >= 1000000000L) {
            until.tv_sec++;
            until.tv_nsec -= 1000000000L;
        }
        pthread_cond_timedwait(&rd->wake, &rd->lock, &until);
        double now = aa_monotonic_seconds();
        for (tracked *t = rd->head.next; t != &rd->head; t = t->next) {
            bool slow_request = t->receiving_since > 0 && now - t->receiving_since > rd->seconds;
            bool slow_reader = t->sending_since > 0 && now - t->sending_since > rd->answer_seconds;
            if (!t->shut && (slow_request || slow_reader)) {
                shutdown(t->fd, SHUT_RDWR);
                t->shut = true;
            }
        }
    }
    pthread_mutex_unlock(&rd->lock);
    return NULL;
}

request_deadline *request_deadline_start(double seconds, double answer_seconds)
{
    request_deadline *rd = calloc(1, sizeof *rd);
    if (!rd)
        return NULL;
    pthread_mutex_init(&rd->lock, NULL);
    pthread_cond_init(&rd->wake, NULL);
    rd->head.next = rd->head.prev = &rd->head;
    rd->seconds = seconds;
    rd->answer_seconds = answer_seconds;
    if (pthread_create(&rd->thread, NULL, watchdog, rd)) {
        pthread_cond_destroy(&rd->wake);
        pthread_mutex_destroy(&rd->lock);
        free(rd);
        return NULL;
    }
    return rd;
}

void request_deadline_stop(request_deadline *rd)
{
    if (!rd)
        return;
    pthread_mutex_lock(&rd->lock);
    rd->stopping = true;
    pthread_cond_signal(&rd->wake);
    pthread_mutex_unlock(&rd->lock);
    pthread_join(rd->thread, NULL);
    /* Connections still tracked belong to a daemon already stopped: their CLOSED callbacks
     * have run, so the list is empty here. */
    pthread_cond_destroy(&rd->wake);
    pthread_mutex_destroy(&rd->lock);
    free(rd);
}

void request_deadline_notify(void *cls, struct MHD_Connection *conn, void **socket_context,
                             enum MHD_ConnectionNotificationCode code)
{
    request_deadline *rd = cls;
    if (code == MHD_CONNECTION_NOTIFY_STARTED) {
        const union MHD_ConnectionInfo *ci =
            MHD_get_connection_info(conn, MHD_CONNECTION_INFO_CONNECTION_FD);
        tracked *t = calloc(1, sizeof *t);
        if (!t || !ci) {
            free(t);
            *socket_context = NULL;
            return;
        }
        t->owner = rd;
        t->fd = ci->connect_fd;
        pthread_mutex_lock(&rd->lock);
        t->receiving_since = aa_monotonic_seconds();
        t->next = rd->head.next;
        t->prev = &rd->head;
        rd->head.next->prev = t;
        rd->head.next = t;
        pthread_mutex_unlock(&rd->lock);
        *socket_context = t;
    } else if (code == MHD_CONNECTION_NOTIFY_CLOSED) {
        tracked *t = *socket_context;
        if (!t)
            return;
        pthread_mutex_lock(&rd->lock);
        t->prev->next = t->next;
        t->next->prev = t->prev;
        pthread_mutex_unlock(&rd->lock);
        free(t);
        *socket_context = NULL;
    }
}

void request_deadline_backdate(void *socket_context, double since)
{
    tracked *t = socket_context;
    if (!t)
        return;
    pthread_mutex_lock(&t->owner->lock);
    if (t->receiving_since > 0 && since < t->receiving_since)
        t->receiving_since = since;
    pthread_mutex_unlock(&t->owner->lock);
}

typedef enum { PHASE_RECEIVING, PHASE_ANSWERING, PHASE_SENDING } phase;

static void set_phase(struct MHD_Connection *conn, phase p)
{
    const union MHD_ConnectionInfo *ci =
        MHD_get_connection_info(conn, MHD_CONNECTION_INFO_SOCKET_CONTEXT);
    tracked *t = ci ? ci->socket_context : NULL;
    if (!t)
        return;
    double now = aa_monotonic_seconds();
    pthread_mutex_lock(&t->owner->lock);
    t->receiving_since = p == PHASE_RECEIVING ? now : 0;
    t->sending_since = p == PHASE_SENDING ? now : 0;
    pthread_mutex_unlock(&t->owner->lock);
}

void request_deadline_received(struct MHD_Connection *conn)
{
    set_phase(conn, PHASE_ANSWERING);
}

void request_deadline_sending(struct MHD_Connection *conn)
{
    set_phase(conn, PHASE_SENDING);
}

void request_deadline_completed(struct MHD_Connection *conn)
{
    set_phase(conn, PHASE_RECEIVING);
}
