/* SPDX-License-Identifier: MIT */
/* Consumer of an installed aenl: a constant signal gives its own value as the conditional mean. */
#include <stdio.h>
#include <string.h>

#include "aenl/aenl.h"

static aenl_moments_t g_m;

int main(void)
{
    aenl_moments_cfg_t c;
    memset(&c, 0, sizeof(c));
    c.x_min = AENL_R(-1.0);
    c.x_max = AENL_R(1.0);
    c.n_grid = 5;
    c.bandwidth = AENL_R(0.6);
    c.n_lags = 1;
    c.lags[0] = 1;
    c.forgetting = AENL_R(1.0);
    if (aenl_moments_init(&g_m, &c) != AENL_OK)
    {
        return 1;
    }
    for (int i = 0; i < 10; ++i)
    {
        aenl_moments_push(&g_m, AENL_R(0.25));
    }
    aenl_moments_point_t p;
    if (aenl_moments_query(&g_m, 0, 2, AENL_DIR_ALL, &p) != AENL_OK ||
        aenl_fabs(p.mean - AENL_R(0.25)) > AENL_R(1e-6))
    {
        return 1;
    }
    printf("consumer ok (%s, mean %.3f)\n", AENL_USE_DOUBLE ? "double" : "float", (double)p.mean);
    return 0;
}
