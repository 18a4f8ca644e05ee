/* SPDX-License-Identifier: MIT */
/* species_map.c: the species maps of `sablier study` (004 §3.4: the fraction of small or light
 * grains on square cells over the piles, summed over samples), their one-line records in a
 * sample's map file, and which species a scene's maps count (declared in study.h). */
#include "study.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

int app_study_species_map_init(AppStudySpeciesMap *map, double L, double cell)
{
    memset(map, 0, sizeof *map);
    if (!(L > 0.0) || !(cell > 0.0) || !isfinite(L) || !isfinite(cell) || L / cell > 4096.0)
        return -1;
    /* columns: one centred on x = 0, then whole columns out to +-L/2 */
    int side = (int)ceil(fmax(0.0, 0.5 * L - 0.5 * cell) / cell - 1e-9);
    map->nx = 2 * side + 1;
    map->ny = (int)fmax(1.0, ceil(L / cell - 1e-9));
    map->cell = cell;
    map->x0 = -0.5 * map->nx * cell;
    map->y0 = 0.0;
    size_t n = (size_t)map->nx * (size_t)map->ny;
    map->count = calloc(n, sizeof *map->count);
    map->marked = calloc(n, sizeof *map->marked);
    if (!map->count || !map->marked) {
        app_study_species_map_free(map);
        return -1;
    }
    return 0;
}

void app_study_species_map_free(AppStudySpeciesMap *map)
{
    free(map->count);
    free(map->marked);
    memset(map, 0, sizeof *map);
}

int app_study_species_map_add(AppStudySpeciesMap *map, const SimFrame *frame, int marked)
{
    int outside = 0;
    for (int g = 0; g < frame->count; ++g) {
        if (frame->flags && (frame->flags[g] & SIM_GRAIN_FIXED))
            continue;
        double u = (frame->x[g] - map->x0) / map->cell, v = (frame->y[g] - map->y0) / map->cell;
        if (!(u >= 0.0 && u < map->nx && v >= 0.0 && v < map->ny)) {
            ++outside;
            continue;
        }
        size_t k = (size_t)(int)v * (size_t)map->nx + (size_t)(int)u;
        ++map->count[k];
        map->marked[k] += (frame->species ? frame->species[g] : 0) == marked;
    }
    return outside;
}

double app_study_species_map_fraction(const AppStudySpeciesMap *map, int i, int j)
{
    if (i < 0 || j < 0 || i >= map->nx || j >= map->ny)
        return (double)NAN;
    size_t k = (size_t)j * (size_t)map->nx + (size_t)i;
    return map->count[k] > 0 ? (double)map->marked[k] / (double)map->count[k] : (double)NAN;
}

int app_study_species_map_format(const AppStudySpeciesMap *map, const char *tag, char *buf,
                                 size_t size)
{
    char none[1];
    if (!buf || size == 0) { /* only the length is wanted */
        buf = none;
        size = sizeof none;
    }
    int total = snprintf(buf, size, "%s,%d,%d", tag, map->nx, map->ny);
    for (size_t k = 0; k < (size_t)map->nx * (size_t)map->ny; ++k) {
        if (map->count[k] == 0)
            continue;
        size_t used = total >= 0 && (size_t)total < size ? (size_t)total : size - 1;
        total +=
            snprintf(buf + used, size - used, ",%zu:%ld:%ld", k, map->count[k], map->marked[k]);
    }
    return total;
}

int app_study_species_map_parse(AppStudySpeciesMap *map, const char *text)
{
    char *end;
    long nx = strtol(text, &end, 10);
    if (*end != ',' || nx != map->nx)
        return -1;
    long ny = strtol(end + 1, &end, 10);
    if (ny != map->ny)
        return -1;
    const char *start = end;
    size_t n = (size_t)map->nx * (size_t)map->ny;
    for (int pass = 0; pass < 2; ++pass) { /* check the whole record, then add it */
        const char *p = start;
        while (*p == ',') {
            long k = strtol(p + 1, &end, 10), c = -1, m = -1;
            if (*end == ':')
                c = strtol(end + 1, &end, 10);
            if (c >= 0 && *end == ':')
                m = strtol(end + 1, &end, 10);
            if (k < 0 || (size_t)k >= n || c < 0 || m < 0 || m > c)
                return -1;
            if (pass == 1) {
                map->count[k] += c;
                map->marked[k] += m;
            }
            p = end;
        }
        if (*p != '\0' && *p != '\n')
            return -1;
    }
    return 0;
}

int app_study_species_marked(const Scene *scene, const char **what)
{
    if (what)
        *what = NULL;
    const AppDischargeDef *def = app_discharge_of(scene);
    if (!def || def->species_count != 2 || !(def->fractions[0] > 0.0) || !(def->fractions[1] > 0.0))
        return -1;
    double d0 = def->diameters[0], d1 = def->diameters[1];
    if (d0 != d1) {
        if (what)
            *what = "small";
        return d0 < d1 ? 0 : 1;
    }
    double r0 = scene->def.materials[0].density, r1 = scene->def.materials[1].density;
    if (r0 != r1) {
        if (what)
            *what = "light";
        return r0 < r1 ? 0 : 1;
    }
    return -1;
}
