/* SPDX-License-Identifier: MIT */
/**
 * @file aenl_json.c
 * @brief See aenl_json.h.
 */
#include <math.h>

#include "aenl_tools/aenl_json.h"

cJSON *aenl_json_num(double v)
{
    return isfinite(v) ? cJSON_CreateNumber(v) : cJSON_CreateNull();
}

int aenl_json_add(cJSON *obj, const char *key, cJSON *item)
{
    if (item == NULL)
    {
        return -1;
    }
    if (!cJSON_AddItemToObject(obj, key, item))
    {
        cJSON_Delete(item);
        return -1;
    }
    return 0;
}
