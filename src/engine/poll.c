/* Progress and stopping inside a step (poll.h). */
#include "poll.h"

#include "engine.h"
#include "timer.h"

/* Set by psim_request_stop, for good: a lock-free atomic int, which a
 * signal handler may store and every thread may load. */
static int stop_asked;

void psim_request_stop(void) { __atomic_store_n(&stop_asked, 1, __ATOMIC_RELAXED); }

int psim_stop_requested(void) { return __atomic_load_n(&stop_asked, __ATOMIC_RELAXED); }

void psim_set_step_progress(psim_sim *e, psim_step_progress_fn fn, void *ctx, double first_s,
                            double every_s)
{
    e->poll.fn = fn;
    e->poll.ctx = ctx;
    e->poll.first_s = first_s;
    e->poll.every_s = every_s;
}

void psim_poll_begin(psim_sim *e)
{
    psim_poll_state *p = &e->poll;
    p->work = 0;
    if (!p->fn)
        return;
    p->start = psim_now();
    p->next = p->start + p->first_s;
}

/* The models' loops see the simulation as const; its poll state is what
 * they may change (atomically). */
static psim_poll_state *state(const psim_sim *e) { return (psim_poll_state *)&e->poll; }

void psim_poll_add(const psim_sim *e, uint64_t work)
{
    __atomic_fetch_add(&state(e)->work, work, __ATOMIC_RELAXED);
}

/* Report now, unless another thread is reporting. */
static void report(const psim_sim *e, psim_poll_state *p, double now, uint64_t done)
{
    if (__atomic_exchange_n(&p->busy, 1, __ATOMIC_ACQUIRE))
        return;
    const char *unit = e->model->work_unit ? e->model->work_unit : "units of work";
    psim_step_progress r = {e->step + 1, now - p->start, done, unit};
    p->fn(p->ctx, &r);
    double next = now + p->every_s;
    __atomic_store(&p->next, &next, __ATOMIC_RELAXED);
    __atomic_store_n(&p->busy, 0, __ATOMIC_RELEASE);
}

int psim_poll(const psim_sim *e, uint64_t work)
{
    psim_poll_state *p = state(e);
    uint64_t done = __atomic_add_fetch(&p->work, work, __ATOMIC_RELAXED);
    if (psim_stop_requested())
        return 1;
    if (!p->fn)
        return 0;
    double now = psim_now(), next;
    __atomic_load(&p->next, &next, __ATOMIC_RELAXED);
    if (now >= next)
        report(e, p, now, done);
    return 0;
}

int psim_engine_stopped(const psim_sim *e, psim_error *err)
{
    psim_error_set(err, "step %ld: interrupted", e->step + 1);
    return -1;
}
