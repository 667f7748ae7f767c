#include "store.h"

#include <string.h>

#include "mem.h"

int psim_store_init(psim_store *s, size_t n)
{
    memset(s, 0, sizeof *s);
    s->n = s->cap = n;
    double **d[] = {&s->x, &s->y, &s->vx, &s->vy, &s->x2, &s->y2, &s->vx2, &s->vy2};
    for (size_t k = 0; k < sizeof d / sizeof d[0]; k++)
        if (!(*d[k] = psim_alloc(n * sizeof(double))))
            goto fail;
    s->id = psim_alloc(n * sizeof(int32_t));
    s->id2 = psim_alloc(n * sizeof(int32_t));
    s->cell = psim_alloc(n * sizeof(uint32_t));
    if (!s->id || !s->id2 || !s->cell)
        goto fail;
    return 0;
fail:
    psim_store_free(s);
    return -1;
}

void psim_store_free(psim_store *s)
{
    void *p[] = {s->x, s->y, s->vx, s->vy, s->x2, s->y2, s->vx2, s->vy2,
                 s->id, s->id2, s->cell};
    for (size_t k = 0; k < sizeof p / sizeof p[0]; k++)
        psim_free(p[k]);
    memset(s, 0, sizeof *s);
}

int psim_store_resize(psim_store *s, size_t n)
{
    if (n <= s->cap) {
        s->n = n;
        return 0;
    }
    psim_store_free(s);
    /* a quarter more: the ghosts and owned particles of a rank vary */
    return psim_store_init(s, n + n / 4) ? -1 : (s->n = n, 0);
}

int psim_store_keep(psim_store *s, size_t n)
{
    if (n <= s->cap) {
        s->n = n;
        return 0;
    }
    psim_store t;
    if (psim_store_init(&t, n + n / 4))
        return -1;
    size_t keep = s->n;
    memcpy(t.x, s->x, keep * sizeof *t.x);
    memcpy(t.y, s->y, keep * sizeof *t.y);
    memcpy(t.vx, s->vx, keep * sizeof *t.vx);
    memcpy(t.vy, s->vy, keep * sizeof *t.vy);
    memcpy(t.id, s->id, keep * sizeof *t.id);
    psim_store_free(s);
    *s = t;
    s->n = n;
    return 0;
}

#define SWAP(a, b) do { __typeof__(a) t_ = (a); (a) = (b); (b) = t_; } while (0)

void psim_store_swap(psim_store *s)
{
    SWAP(s->x, s->x2);
    SWAP(s->y, s->y2);
    SWAP(s->vx, s->vx2);
    SWAP(s->vy, s->vy2);
    SWAP(s->id, s->id2);
}
