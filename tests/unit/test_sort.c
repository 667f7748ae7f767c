/* The parallel counting sort by cell: order, stability, chunk independence. */
#include <stdlib.h>
#include <string.h>

#include "check.h"
#include "engine/grid.h"
#include "engine/sort.h"
#include "engine/store.h"

static double rnd(unsigned *s)
{
    *s = *s * 1103515245u + 12345u;
    return (double)(*s >> 8) / (double)(1u << 24);
}

static void fill(psim_store *st, size_t n, double L)
{
    unsigned s = 7;
    for (size_t i = 0; i < n; i++) {
        /* 10% of the disks outside the box */
        double span = (i % 10 == 0) ? 3 * L : L, off = (i % 10 == 0) ? -L : 0;
        st->x[i] = off + rnd(&s) * span;
        st->y[i] = off + rnd(&s) * span;
        st->vx[i] = (double)i;
        st->vy[i] = -(double)i;
        st->id[i] = (int32_t)i;
    }
}

static void test_sort(int threads, const psim_store *ref_after)
{
    const size_t n = 5000;
    psim_grid g;
    psim_store st;
    psim_sorter so;
    CHECK(psim_grid_init(&g, 100.0, 0.5, 2.0 * (0.5), (long)n, 0, NULL) == 0);
    CHECK(psim_store_init(&st, n) == 0);
    CHECK(psim_sorter_init(&so, threads, g.ncells) == 0);
    fill(&st, n, 100.0);
    psim_thread_stats ts[16];
    memset(ts, 0, sizeof ts);
    psim_sort_by_cell(&so, &st, &g, threads, ts);
    uint64_t handled = 0;
    for (int k = 0; k < threads; k++)
        handled += ts[k].particles[PSIM_PHASE_SORT];
    CHECK(handled == n);

    CHECK(g.cellstart[0] == 0 && g.cellstart[g.ncells] == n);
    char *seen = calloc(n, 1);
    for (uint32_t c = 0; c < g.ncells; c++) {
        CHECK(g.cellstart[c] <= g.cellstart[c + 1]);
        for (uint32_t i = g.cellstart[c]; i < g.cellstart[c + 1]; i++) {
            CHECK(psim_grid_cell(&g, st.x[i], st.y[i]) == c);
            /* stable: input was in id order */
            CHECK(i == g.cellstart[c] || st.id[i] > st.id[i - 1]);
            /* the whole particle moved together */
            CHECK(st.vx[i] == (double)st.id[i] && st.vy[i] == -(double)st.id[i]);
            seen[st.id[i]]++;
        }
    }
    for (size_t i = 0; i < n; i++)
        CHECK(seen[i] == 1);
    free(seen);

    /* sorting again changes nothing */
    CHECK(psim_sort_by_cell(&so, &st, &g, threads, NULL) == 0);
    if (ref_after) {
        CHECK(memcmp(ref_after->id, st.id, n * sizeof *st.id) == 0);
        CHECK(memcmp(ref_after->x, st.x, n * sizeof *st.x) == 0);
    }
    psim_sorter_free(&so);
    psim_grid_free(&g);
    if (!ref_after) {
        static psim_store keep;
        keep = st;
        test_sort(2, &keep);
        test_sort(3, &keep);
        test_sort(16, &keep);
        psim_store_free(&keep);
        return;
    }
    psim_store_free(&st);
}

int main(void)
{
    test_sort(1, NULL);
    return check_done();
}
