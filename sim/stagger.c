/* SPDX-License-Identifier: MIT */
/* stagger.c: blocks whose data begin at different places within their pages, so that arrays read
 * at the same index in one loop do not all fall into one set of the L1 cache (docs/dev/scaling.md,
 * "the grain arrays staggered within their pages" and "the list's arrays staggered"). */
#include "internal.h"

#include <stdlib.h>

/* Each block begins with its lead (a size_t at the data's start minus one) before the data. */
static size_t lead_of(const void *data)
{
    return ((const size_t *)data)[-1];
}

void *sim_stagger_grow(void *data, size_t bytes, int k)
{
    const size_t lead = data ? lead_of(data) : sim_stagger_lead(k);
    char *block = data ? (char *)data - lead : NULL;
    char *grown = realloc(block, lead + (bytes > 0 ? bytes : 1));
    if (!grown)
        return NULL;
    ((size_t *)(void *)(grown + lead))[-1] = lead;
    return grown + lead;
}

void sim_stagger_free(void *data)
{
    if (data)
        free((char *)data - lead_of(data));
}

size_t sim_stagger_offset(const void *data)
{
    return data ? lead_of(data) : 0;
}
