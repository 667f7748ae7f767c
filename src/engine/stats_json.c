/* --stats FILE: the run's statistics as JSON. */
#include <math.h>
#include <stdio.h>

#include "engine.h"
#include "mem.h"

int psim_write_stats_json(FILE *f, const psim_sim *e, const char *scene_name,
                          double total_s, const char *extra)
{
    const psim_stats *s = &e->stats;
    char L[PSIM_FORMAT_MAX], r[PSIM_FORMAT_MAX], dt[PSIM_FORMAT_MAX] = "null";
    psim_format_double(L, e->L, -1);
    psim_format_double(r, e->r, -1);
    if (isfinite(e->step_time))
        psim_format_double(dt, e->step_time, -1);
    fprintf(f, "{\n  \"psim_version\": \"%s\",\n  \"model\": \"%s\",\n  \"scene\": ",
            PSIM_VERSION, e->model->name);
    psim_write_json_string(f, scene_name ? scene_name : "");
    fprintf(f, ",\n  \"n\": %ld,\n  \"L\": %s,\n  \"r\": %s,\n  \"steps\": %ld,\n"
               "  \"step_time\": %s,\n  \"threads\": %d,\n  \"allocator\": \"%s\",\n",
            e->n_all, L, r, s->steps, dt, s->threads, psim_allocator_name());
    char h[PSIM_FORMAT_MAX] = "null";   /* JSON has no infinity */
    if (isfinite(s->cell_side))
        psim_format_double(h, s->cell_side, -1);
    fprintf(f, "  \"grid_cells\": %d,\n  \"cell_side\": %s,\n  \"tile_cells\": %d,\n"
               "  \"tiles\": %d,\n  \"tiles_cut\": %s,\n",
            s->grid_cells, h, s->tile_cells, s->tiles, s->tiles_cut ? "true" : "false");
    fprintf(f, "  \"time_s\": %.6f,\n  \"phases_s\": {", total_s);
    for (int p = 0; p < s->nphases; p++)
        fprintf(f, "%s\"%s\": %.6f", p ? ", " : "", s->phase_name[p], s->phase_s[p]);
    fprintf(f, "}");
    for (int k = 0; k < s->ncounters; k++)
        fprintf(f, ",\n  \"%s\": %llu", s->counter_name[k],
                (unsigned long long)s->counter[k]);
    for (int k = 0; k < s->nvalues; k++)
        if (isfinite(s->value[k]))
            fprintf(f, ",\n  \"%s\": %.17g", s->value_name[k], s->value[k]);
        else
            fprintf(f, ",\n  \"%s\": null", s->value_name[k]);
    fprintf(f, ",\n  \"left_out\": {");
    for (int k = 0; k < s->nskips; k++)
        fprintf(f, "%s\"%s\": %llu", k ? ", " : "", s->skip_name[k],
                (unsigned long long)s->skipped[k]);
    fprintf(f, "}");
    fprintf(f, "%s\n%s}\n", extra ? "," : "", extra ? extra : "");
    return ferror(f) ? -1 : 0;
}
