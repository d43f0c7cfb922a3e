/* SPDX-License-Identifier: MIT */
/**
 * @file aenl_json.h
 * @brief The two helpers every JSON writer of the host tools needs (cJSON documents).
 */
#ifndef AENL_TOOLS_JSON_H
#define AENL_TOOLS_JSON_H

#include <cjson/cJSON.h>

/** v as a JSON number, or null when it is not finite (JSON has no NaN or infinity); NULL when
 *  memory runs out. */
cJSON *aenl_json_num(double v);

/** item under key into obj. Returns 0, or -1 when item is NULL (memory ran out making it) or
 *  cannot be added (it is freed then), so that a writer can or its results and fail once. */
int aenl_json_add(cJSON *obj, const char *key, cJSON *item);

#endif /* AENL_TOOLS_JSON_H */
