/* Wall-clock timers around phases (CoMD's performanceTimers, in small),
 * and LIKWID marker regions around the same phases. */
#ifndef PSIM_ENGINE_TIMER_H
#define PSIM_ENGINE_TIMER_H

double psim_now(void); /* seconds, monotonic */

/* LIKWID marker regions (cmake -DPSIM_LIKWID=ON; docs/profiling.md).  Under
 * `likwid-perfctr -m`, every phase psim times is a region named as psim
 * names the phase, so that likwid-perfctr reports each phase's counters.
 * A region is opened and closed where the phase's wall time is taken, in
 * every thread of the team (psim_region_begin forks the team to do it), or
 * where a phase's work is spread over work items that interleave with
 * another phase's, in the thread that runs the item (psim_region_thread_*).
 * Outside likwid-perfctr -m the calls return at once; in other builds they
 * are empty and cost nothing. */
#ifdef PSIM_LIKWID
/* Once, before OpenMP starts its threads: starts LIKWID's marker API when
 * psim runs under likwid-perfctr -m. */
void psim_markers_init(void);
/* Once, before the first region: every thread of the team registers with
 * LIKWID (which, under likwid-perfctr -C, pins each to a CPU of its own). */
void psim_markers_threads(int threads);
/* Once, after the last region: LIKWID writes the regions' counts for
 * likwid-perfctr to report. */
void psim_markers_close(void);
void psim_region_begin(int threads, const char *name);
void psim_region_end(int threads, const char *name);
void psim_region_thread_begin(const char *name);
void psim_region_thread_end(const char *name);
#else
#define psim_markers_init() ((void)0)
#define psim_markers_threads(threads) ((void)0)
#define psim_markers_close() ((void)0)
#define psim_region_begin(threads, name) ((void)0)
#define psim_region_end(threads, name) ((void)0)
#define psim_region_thread_begin(name) ((void)0)
#define psim_region_thread_end(name) ((void)0)
#endif

#endif
