/* The move: accepted collisions, then free flight for every other disk.
 * Each disk is in at most one accepted collision, which reads and writes
 * only its own disks, so both loops run in parallel with no ordering. */
#include <omp.h>

#include "ccd.h"
#include "rules.h"
#include "../../engine/tstats.h"

void ccd_advance(psim_sim *e, cmodel *m)
{
    psim_store *s = &e->st;
    const size_t n = s->n, na = m->acc.n;
#pragma omp parallel num_threads(e->threads)
    {
        double t0 = psim_now();
        uint64_t walls = 0;
#pragma omp for schedule(static)
        for (size_t k = 0; k < na; k++) {
            ccd_apply(&m->acc.c[k], s->x, s->y, s->vx, s->vy, m->pcoll, m->wcoll, m->L, m->r);
            walls += m->acc.c[k].q < 0;
        }
        int T = omp_get_num_threads(), me = omp_get_thread_num();
        size_t lo = psim_part_lo(n, T, me), hi = psim_part_lo(n, T, me + 1);
        for (size_t i = lo; i < hi; i++)
            if (!m->busy[i]) {
                s->x[i] += s->vx[i];
                s->y[i] += s->vy[i];
            }
#pragma omp barrier
        /* busy flags back to 0 for the next step: only accepted
         * collisions set them, and each disk is in at most one (clearing
         * by every candidate would have two threads write one flag) */
#pragma omp for schedule(static)
        for (size_t k = 0; k < na; k++) {
            m->busy[m->acc.c[k].sp] = 0;
            if (m->acc.c[k].q >= 0)
                m->busy[m->acc.c[k].sq] = 0;
        }
        psim_tstat_add(e->tstats, PSIM_PHASE_MOVE, psim_now() - t0, 1, hi - lo);
        if (e->tstats)
            e->tstats[me].wall_resolutions += walls;
    }
    for (size_t k = 0; m->rank == 0 && k < na; k++)   /* (over ranks: rank 0 counts) */
        e->stats.counter[m->acc.c[k].q < 0 ? CC_WALL_COLLISIONS : CC_PAIR_COLLISIONS]++;
}
