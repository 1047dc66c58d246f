/*
 * device_pool.c: worker processes, one per device, fed frame numbers from one queue (see
 * device_pool.h). Parent and worker talk through two pipes per worker: frame numbers go down,
 * fixed-size reports come up, from the worker's render loop (started, ready for a frame, failed)
 * and from its writer threads (a file written, a write failed). A report is smaller than PIPE_BUF,
 * so it arrives whole or not at all; a pipe that ends (EOF) is a worker that is gone, whatever
 * killed it.
 */
#define _POSIX_C_SOURCE 200809L
#include "device_pool.h"

#include <errno.h>
#include <limits.h>
#include <poll.h>
#include <stdlib.h>
#include <string.h>
#include <sys/wait.h>
#include <unistd.h>

#include "clock.h"

/* The frame number that tells a worker to finish. */
static const uint32_t stop_word = UINT32_MAX;

typedef enum report_kind {
    REPORT_STARTED = 1, /* and ready for a frame */
    REPORT_READY,       /* for another frame */
    REPORT_DONE,        /* a frame's file is written */
    REPORT_FAILED,
    REPORT_FAILED_AT_END
} report_kind;

/* What a worker writes up its pipe, whole in one write(). */
typedef struct report {
    uint32_t kind;          /* report_kind */
    uint32_t frame;         /* DONE: the frame written */
    vkrt_pool_frame result; /* DONE */
    union {
        vkrt_pool_start started; /* STARTED */
        char failure[1024];      /* FAILED: why */
    } text;
} report;

_Static_assert(sizeof(report) <= PIPE_BUF, "a report must reach the parent in one piece");

typedef enum frame_state { FRAME_WAITING = 0, FRAME_IN_FLIGHT, FRAME_DONE } frame_state;

/* The parent's view of one worker. */
typedef struct worker_link {
    pid_t pid;
    int to_worker, from_worker; /* the parent's ends of the two pipes; -1 once closed */
    bool started, ready;        /* ready: it asked for a frame and was given none yet */
    uint32_t held;              /* frames given to it whose files it has not reported */
    double started_ms;          /* when it said it started */
} worker_link;

/* write() (out) or read() exactly size bytes, through interruptions; false at the end of the
 * pipe or on an error. */
static bool transfer_all(int fd, void *data, size_t size, bool out)
{
    char *p = data;
    while (size > 0) {
        ssize_t n = out ? write(fd, p, size) : read(fd, p, size);
        if (n < 0 && errno == EINTR)
            continue;
        if (n <= 0)
            return false;
        p += n;
        size -= (size_t)n;
    }
    return true;
}

static bool write_all(int fd, const void *data, size_t size)
{
    return transfer_all(fd, (void *)data, size, true);
}

static bool read_all(int fd, void *data, size_t size)
{
    return transfer_all(fd, data, size, false);
}

static void close_fd(int *fd)
{
    if (*fd >= 0)
        close(*fd);
    *fd = -1;
}

/* ------------------------------------------------------------------ the worker process */

static void send_failure(int fd, report_kind kind, const vkrt_error *err)
{
    report r = {.kind = kind};
    snprintf(r.text.failure, sizeof r.text.failure, "%s", err->msg);
    write_all(fd, &r, sizeof r);
}

void vkrt_pool_report_written(vkrt_pool_reporter *reporter, uint32_t frame,
                              const vkrt_pool_frame *result)
{
    report r = {.kind = REPORT_DONE, .frame = frame, .result = *result};
    /* A parent that is gone makes this fail; the worker then reads the end of its frame pipe. */
    write_all(reporter->fd, &r, sizeof r);
}

void vkrt_pool_report_failed(vkrt_pool_reporter *reporter, const vkrt_error *err)
{
    atomic_store(&reporter->failed, 1);
    send_failure(reporter->fd, REPORT_FAILED, err);
}

/* The worker's life, in the child process; never returns. */
_Noreturn static void worker_main(const vkrt_device_pool_desc *desc, uint32_t index,
                                  int from_parent, int to_parent)
{
    /* Ctrl-C reaches the whole process group: the parent decides, and lets the frames being
     * rendered finish. A worker whose parent is gone reads the end of its pipe and stops. */
    signal(SIGINT, SIG_IGN);
    signal(SIGTERM, SIG_IGN);
    vkrt_error err = {{0}};
    vkrt_pool_reporter reporter = {.fd = to_parent};
    report r = {.kind = REPORT_STARTED};
    if (!desc->start(desc->user, index, desc->devices[index], &reporter, &r.text.started, &err)) {
        send_failure(to_parent, REPORT_FAILED, &err);
        _exit(1);
    }
    bool ok = write_all(to_parent, &r, sizeof r);
    uint32_t frame;
    while (ok && read_all(from_parent, &frame, sizeof frame) && frame != stop_word) {
        if (!desc->render(desc->user, frame, &err)) {
            send_failure(to_parent, REPORT_FAILED, &err);
            ok = false;
            break;
        }
        r = (report){.kind = REPORT_READY};
        ok = write_all(to_parent, &r, sizeof r);
    }
    /* A write that failed on another thread has been reported already; it ends the pipe. */
    ok = ok && !atomic_load(&reporter.failed);
    if (desc->finish && !desc->finish(desc->user, ok, &err) && ok) {
        send_failure(to_parent, REPORT_FAILED_AT_END, &err);
        ok = false;
    }
    _exit(ok && !atomic_load(&reporter.failed) ? 0 : 1);
}

/* ------------------------------------------------------------------ the parent */

/* How a worker process ended, in words, for its failure report. */
static void describe_exit(pid_t pid, char *text, size_t size)
{
    int status;
    pid_t got;
    do
        got = waitpid(pid, &status, 0);
    while (got < 0 && errno == EINTR);
    if (got < 0)
        snprintf(text, size, "its process was lost (%s)", strerror(errno));
    else if (WIFSIGNALED(status))
        snprintf(text, size, "killed by signal %d (%s)", WTERMSIG(status),
                 strsignal(WTERMSIG(status)));
    else if (WEXITSTATUS(status) != 0)
        snprintf(text, size, "exited with status %d", WEXITSTATUS(status));
    else
        text[0] = '\0';
}

typedef struct pool_run {
    const vkrt_device_pool_desc *desc;
    vkrt_pool_result *result;
    worker_link links[VKRT_POOL_MAX_WORKERS];
    uint8_t *state; /* frame_state of each of desc->frames */
    uint8_t *owner; /* the worker that holds each frame in flight */
    uint32_t next;  /* no frame before this one is waiting */
    uint32_t in_flight;
    uint32_t alive;  /* workers whose report pipe is still open */
    double start_ms; /* when the run began */
} pool_run;

/* The worker's process is gone or going (its pipe ended): collects how it ended, and puts the
 * frame it held back in the queue. */
static void worker_ended(pool_run *p, uint32_t w)
{
    worker_link *l = &p->links[w];
    vkrt_pool_worker *out = &p->result->workers[w];
    close_fd(&l->to_worker);
    close_fd(&l->from_worker);
    --p->alive;
    char how[256];
    describe_exit(l->pid, how, sizeof how);
    /* A worker that said why it failed exits with status 1: its words say more. */
    if (how[0] && !out->failed) {
        snprintf(out->failure, sizeof out->failure, "%s", how);
        out->failed = true;
    }
    l->ready = false;
    for (uint32_t i = 0; l->held > 0 && i < p->desc->frame_count; ++i) {
        if (p->state[i] != FRAME_IN_FLIGHT || p->owner[i] != w)
            continue;
        if (!out->lost_frame)
            out->lost_frame_number = p->desc->frames[i];
        out->lost_frame = true;
        ++out->lost_frames;
        p->state[i] = FRAME_WAITING;
        if (i < p->next)
            p->next = i;
        --p->in_flight;
        --l->held;
        out->failed = true;
        if (!out->failure[0])
            snprintf(out->failure, sizeof out->failure, "its process ended");
    }
}

/* Gives a worker that asked for a frame the next waiting one, if any and not stopped. */
static void hand_out(pool_run *p, uint32_t w)
{
    worker_link *l = &p->links[w];
    const vkrt_device_pool_desc *desc = p->desc;
    if (!l->ready || l->to_worker < 0 || (desc->stop && *desc->stop))
        return;
    while (p->next < desc->frame_count && p->state[p->next] != FRAME_WAITING)
        ++p->next;
    if (p->next == desc->frame_count)
        return;
    uint32_t i = p->next;
    /* A write to a worker that just died fails (EPIPE): its report pipe's end says so next. */
    if (!write_all(l->to_worker, &desc->frames[i], sizeof desc->frames[i])) {
        close_fd(&l->to_worker);
        return;
    }
    p->state[i] = FRAME_IN_FLIGHT;
    p->owner[i] = (uint8_t)w;
    ++p->in_flight;
    ++l->held;
    l->ready = false;
}

/* The index in desc->frames of frame, in flight with worker w; frame_count if none is. */
static uint32_t held_index(const pool_run *p, uint32_t w, uint32_t frame)
{
    for (uint32_t i = 0; i < p->desc->frame_count; ++i)
        if (p->desc->frames[i] == frame && p->state[i] == FRAME_IN_FLIGHT && p->owner[i] == w)
            return i;
    return p->desc->frame_count;
}

/* Worker w's file of frame is written. */
static void frame_written(pool_run *p, uint32_t w, const report *r)
{
    uint32_t i = held_index(p, w, r->frame);
    if (i == p->desc->frame_count)
        return; /* not a frame it holds: ignored */
    worker_link *l = &p->links[w];
    vkrt_pool_worker *out = &p->result->workers[w];
    p->state[i] = FRAME_DONE;
    --p->in_flight;
    --l->held;
    ++out->frames;
    out->seconds = (vkrt_clock_ms() - l->started_ms) * 1e-3;
    out->gpu_seconds += r->result.gpu_seconds;
    out->rays += r->result.rays;
    ++p->result->rendered;
    if (p->desc->frame_done)
        p->desc->frame_done(p->desc->user, r->frame, p->result->rendered, w);
}

/* Reads one report of worker w (its pipe is readable). */
static void read_report(pool_run *p, uint32_t w)
{
    worker_link *l = &p->links[w];
    vkrt_pool_worker *out = &p->result->workers[w];
    report r;
    if (!read_all(l->from_worker, &r, sizeof r)) {
        worker_ended(p, w);
        return;
    }
    if (r.kind == REPORT_STARTED) {
        l->started = l->ready = true;
        l->started_ms = vkrt_clock_ms();
        r.text.started.device_name[sizeof r.text.started.device_name - 1] = '\0';
        r.text.started.about[sizeof r.text.started.about - 1] = '\0';
        snprintf(out->device_name, sizeof out->device_name, "%s", r.text.started.device_name);
        if (p->result->start_seconds == 0)
            p->result->start_seconds = (vkrt_clock_ms() - p->start_ms) * 1e-3;
        if (!p->result->about[0])
            snprintf(p->result->about, sizeof p->result->about, "%s", r.text.started.about);
    } else if (r.kind == REPORT_READY) {
        l->ready = true;
    } else if (r.kind == REPORT_DONE) {
        frame_written(p, w, &r);
    } else if (r.kind == REPORT_FAILED || r.kind == REPORT_FAILED_AT_END) {
        /* The worker exits next; its held frame goes back when its pipe ends. */
        out->failed = true;
        out->failed_at_end = r.kind == REPORT_FAILED_AT_END;
        r.text.failure[sizeof r.text.failure - 1] = '\0';
        snprintf(out->failure, sizeof out->failure, "%s", r.text.failure);
        close_fd(&l->to_worker);
    }
}

static void close_pipes(int (*pipes)[2], int count)
{
    for (int i = 0; i < count; ++i) {
        close(pipes[i][0]);
        close(pipes[i][1]);
    }
}

/* Makes count pipes and forks; on failure nothing is left open. *pid as fork() gives it. */
static bool fork_with_pipes(int (*pipes)[2], int count, pid_t *pid, vkrt_error *err)
{
    for (int i = 0; i < count; ++i)
        if (pipe(pipes[i]) != 0) {
            close_pipes(pipes, i);
            return vkrt_error_set(err, "--devices: cannot make a pipe: %s", strerror(errno));
        }
    /* What the parent's stdio holds must not be written twice. */
    fflush(NULL);
    *pid = fork();
    if (*pid < 0) {
        close_pipes(pipes, count);
        return vkrt_error_set(err, "--devices: cannot start a process: %s", strerror(errno));
    }
    return true;
}

/* Starts worker w: its two pipes (frames down, reports up) and its process. */
static bool start_worker(pool_run *p, uint32_t w, vkrt_error *err)
{
    enum { down, up };
    int pipes[2][2];
    pid_t pid;
    if (!fork_with_pipes(pipes, 2, &pid, err))
        return false;
    if (pid == 0) {
        /* The earlier workers' ends stay with the parent: a worker holding another's pipe would
         * keep that one from seeing its parent go. */
        for (uint32_t i = 0; i < w; ++i) {
            close_fd(&p->links[i].to_worker);
            close_fd(&p->links[i].from_worker);
        }
        close(pipes[down][1]);
        close(pipes[up][0]);
        worker_main(p->desc, w, pipes[down][0], pipes[up][1]);
    }
    close(pipes[down][0]);
    close(pipes[up][1]);
    p->links[w] =
        (worker_link){.pid = pid, .to_worker = pipes[down][1], .from_worker = pipes[up][0]};
    ++p->alive;
    return true;
}

/* Waits for reports and hands out frames until every frame is written, or stopped with none in
 * flight, or no worker is left. */
static void serve(pool_run *p)
{
    const vkrt_device_pool_desc *desc = p->desc;
    uint32_t n = desc->worker_count;
    while (p->alive > 0 && p->result->rendered < desc->frame_count &&
           !(desc->stop && *desc->stop && p->in_flight == 0)) {
        struct pollfd fds[VKRT_POOL_MAX_WORKERS];
        uint32_t owner[VKRT_POOL_MAX_WORKERS], count = 0;
        for (uint32_t w = 0; w < n; ++w)
            if (p->links[w].from_worker >= 0) {
                fds[count] = (struct pollfd){.fd = p->links[w].from_worker, .events = POLLIN};
                owner[count++] = w;
            }
        if (poll(fds, count, -1) < 0)
            continue; /* EINTR: a signal, perhaps the one that stops us */
        for (uint32_t i = 0; i < count; ++i)
            if (fds[i].revents)
                read_report(p, owner[i]);
        for (uint32_t w = 0; w < n; ++w)
            hand_out(p, w);
    }
}

/* Tells every worker left to finish and waits for each, reading its last reports. */
static void finish_workers(pool_run *p)
{
    for (uint32_t w = 0; w < p->desc->worker_count; ++w) {
        worker_link *l = &p->links[w];
        if (l->to_worker >= 0)
            write_all(l->to_worker, &stop_word, sizeof stop_word);
        close_fd(&l->to_worker);
    }
    for (uint32_t w = 0; w < p->desc->worker_count; ++w)
        while (p->links[w].from_worker >= 0)
            read_report(p, w);
}

bool vkrt_device_pool_run(const vkrt_device_pool_desc *desc, vkrt_pool_result *result,
                          vkrt_error *err)
{
    memset(result, 0, sizeof *result);
    if (desc->worker_count < 1 || desc->worker_count > VKRT_POOL_MAX_WORKERS)
        return vkrt_error_set(err, "--devices: %u workers; from 1 to %d can run",
                              desc->worker_count, VKRT_POOL_MAX_WORKERS);
    pool_run p = {.desc = desc, .result = result};
    p.state = calloc(desc->frame_count ? desc->frame_count : 1, 1);
    p.owner = calloc(desc->frame_count ? desc->frame_count : 1, 1);
    if (!p.state || !p.owner) {
        free(p.state);
        free(p.owner);
        return vkrt_error_set(err, "out of memory");
    }
    result->worker_count = desc->worker_count;
    for (uint32_t w = 0; w < desc->worker_count; ++w) {
        result->workers[w].device = desc->devices[w];
        p.links[w] = (worker_link){.to_worker = -1, .from_worker = -1};
    }
    signal(SIGPIPE, SIG_IGN);
    p.start_ms = vkrt_clock_ms();
    bool ok = true;
    for (uint32_t w = 0; ok && w < desc->worker_count; ++w)
        ok = start_worker(&p, w, err);
    if (ok)
        serve(&p);
    finish_workers(&p);
    result->interrupted = desc->stop && *desc->stop && result->rendered < desc->frame_count;
    result->seconds = (vkrt_clock_ms() - p.start_ms) * 1e-3;
    free(p.state);
    free(p.owner);
    return ok;
}

/* ------------------------------------------------------------------ devices */

bool vkrt_device_pool_list(bool (*list)(FILE *out, vkrt_error *err), char *text, size_t size,
                           uint32_t *device_count, vkrt_error *err)
{
    int pipes[1][2];
    pid_t pid;
    if (!fork_with_pipes(pipes, 1, &pid, err))
        return false;
    int *fds = pipes[0];
    if (pid == 0) {
        close(fds[0]);
        FILE *out = fdopen(fds[1], "w");
        vkrt_error child_err = {{0}};
        bool listed = out && list(out, &child_err);
        if (out && !listed)
            fputs(child_err.msg, out);
        _exit(out && fclose(out) == 0 && listed ? 0 : 1);
    }
    close(fds[1]);
    size_t used = 0;
    for (;;) {
        char chunk[512];
        ssize_t n = read(fds[0], chunk, sizeof chunk);
        if (n < 0 && errno == EINTR)
            continue;
        if (n <= 0)
            break;
        size_t take = (size_t)n < size - 1 - used ? (size_t)n : size - 1 - used;
        memcpy(text + used, chunk, take);
        used += take;
    }
    close(fds[0]);
    while (used > 0 && text[used - 1] == '\n')
        --used;
    text[used] = '\0';
    char how[256];
    describe_exit(pid, how, sizeof how);
    if (how[0])
        return vkrt_error_set(err, "listing the Vulkan devices failed: %s%s%s", text,
                              text[0] ? "; " : "", how);
    *device_count = 0;
    for (const char *line = text; *line; ++line) {
        if ((line == text || line[-1] == '\n') && *line >= '0' && *line <= '9')
            ++*device_count;
    }
    return true;
}

/* Reads the device indices of spec into devices (NULL: only checks); count how many. */
static bool read_indices(const char *spec, int *devices, uint32_t *count, vkrt_error *err)
{
    const char *p = spec;
    *count = 0;
    for (;;) {
        char *end;
        errno = 0;
        long index = *p >= '0' && *p <= '9' ? strtol(p, &end, 10) : -1;
        if (index < 0 || index > 1000 || errno || (*end != ',' && *end != '\0'))
            return vkrt_error_set(err,
                                  "--devices: '%s' is not 'all' or device numbers separated "
                                  "by commas, e.g. 0,2 (vkrt --list-devices)",
                                  spec);
        if (*count == VKRT_POOL_MAX_WORKERS)
            return vkrt_error_set(err, "--devices: '%s' asks for more than %d workers", spec,
                                  VKRT_POOL_MAX_WORKERS);
        if (devices)
            devices[*count] = (int)index;
        ++*count;
        if (*end == '\0')
            return true;
        p = end + 1;
    }
}

bool vkrt_devices_spec_check(const char *spec, vkrt_error *err)
{
    uint32_t count;
    return strcmp(spec, "all") == 0 || read_indices(spec, NULL, &count, err);
}

bool vkrt_devices_spec_parse(const char *spec, uint32_t device_count, const char *listing,
                             int *devices, uint32_t *worker_count, vkrt_error *err)
{
    if (device_count == 0)
        return vkrt_error_set(err, "--devices %s: there is no Vulkan device", spec);
    if (strcmp(spec, "all") == 0) {
        *worker_count = device_count < VKRT_POOL_MAX_WORKERS ? device_count : VKRT_POOL_MAX_WORKERS;
        for (uint32_t i = 0; i < *worker_count; ++i)
            devices[i] = (int)i;
        return true;
    }
    if (!read_indices(spec, devices, worker_count, err))
        return false;
    for (uint32_t i = 0; i < *worker_count; ++i)
        if ((uint32_t)devices[i] >= device_count)
            return vkrt_error_set(err, "--devices %s: there is no device %d; the %u device%s:\n%s",
                                  spec, devices[i], device_count, device_count == 1 ? "" : "s",
                                  listing);
    return true;
}
