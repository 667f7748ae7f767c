/* --stats FILE: the run's statistics as JSON. */
#include <math.h>
#include <stdio.h>

#include "scene.h"
#include "../engine/engine.h"
#include "../engine/mem.h"

const char *psim_allocator(void) { return psim_allocator_name(); }

const char *psim_version(void) { return PSIM_VERSION; }

/* Length of the well-formed UTF-8 sequence at s (1-4), or 0 when it is
 * not one (a stray or missing continuation byte, an overlong form, a
 * surrogate, past U+10FFFF). */
static int utf8_len(const unsigned char *s)
{
    unsigned c = s[0], n = c >= 0xf0 ? 4 : c >= 0xe0 ? 3 : c >= 0xc0 ? 2 : 0;
    if (c < 0x80)
        return 1;
    if (n == 0 || c > 0xf4)
        return 0;
    unsigned cp = c & (0x7fu >> n);
    for (unsigned k = 1; k < n; k++) {
        if ((s[k] & 0xc0) != 0x80)
            return 0;
        cp = cp << 6 | (s[k] & 0x3fu);
    }
    static const unsigned least[5] = {0, 0, 0x80, 0x800, 0x10000};
    if (cp < least[n] || cp > 0x10ffff || (cp >= 0xd800 && cp <= 0xdfff))
        return 0;
    return (int)n;
}

/* s as a JSON string: quotes, backslashes and control characters escaped,
 * and a byte that is not part of well-formed UTF-8 (a file name in another
 * encoding) written as U+FFFD, so the file stays valid JSON. */
void psim_write_json_string(FILE *f, const char *s)
{
    fputc('"', f);
    const unsigned char *p = (const unsigned char *)(s ? s : "");
    while (*p) {
        int n = utf8_len(p);
        if (n == 0) {
            fputs("\\ufffd", f);
            p++;
        } else if (*p == '"' || *p == '\\') {
            fprintf(f, "\\%c", *p++);
        } else if (*p < 0x20) {
            fprintf(f, "\\u%04x", *p++);
        } else {
            fwrite(p, 1, (size_t)n, f);
            p += n;
        }
    }
    fputc('"', f);
}

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
            e->n, L, r, s->steps, dt, s->threads, psim_allocator_name());
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
