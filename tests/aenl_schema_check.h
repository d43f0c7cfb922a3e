/* SPDX-License-Identifier: MIT */
/**
 * @file aenl_schema_check.h
 * @brief Test support: a JSON Schema (draft 2020-12) validator for the keywords the project's
 *        schemas in docs/schema use, and only those: type (a name or a list of names), enum,
 *        required, properties, additionalProperties (false), items, minItems, maxItems,
 *        minimum, maximum and $ref to "#/$defs/NAME". A schema that uses any other keyword is
 *        refused, so a schema cannot silently say more than is checked.
 */
#ifndef AENL_SCHEMA_CHECK_H
#define AENL_SCHEMA_CHECK_H

#include <math.h>
#include <stdio.h>
#include <string.h>

#include <cjson/cJSON.h>

/* The first failure: where (a JSON pointer into the instance) and why. */
typedef struct
{
    char where[256];
    char why[256];
} schema_fail_t;

static int schema_fail(schema_fail_t *f, const char *where, const char *why, const char *what)
{
    (void)snprintf(f->where, sizeof(f->where), "%s", where[0] != '\0' ? where : "/");
    (void)snprintf(f->why, sizeof(f->why), "%s%s", why, what != NULL ? what : "");
    return 0;
}

static int schema_type_is(const cJSON *v, const char *t)
{
    if (strcmp(t, "object") == 0)
    {
        return cJSON_IsObject(v);
    }
    if (strcmp(t, "array") == 0)
    {
        return cJSON_IsArray(v);
    }
    if (strcmp(t, "string") == 0)
    {
        return cJSON_IsString(v);
    }
    if (strcmp(t, "boolean") == 0)
    {
        return cJSON_IsBool(v);
    }
    if (strcmp(t, "null") == 0)
    {
        return cJSON_IsNull(v);
    }
    if (strcmp(t, "number") == 0)
    {
        return cJSON_IsNumber(v);
    }
    if (strcmp(t, "integer") == 0)
    {
        return cJSON_IsNumber(v) && !(fabs(v->valuedouble - floor(v->valuedouble)) > 0.0);
    }
    return -1; /* not a type name */
}

static int schema_equal(const cJSON *a, const cJSON *b)
{
    if (cJSON_IsNull(a) || cJSON_IsNull(b))
    {
        return cJSON_IsNull(a) && cJSON_IsNull(b);
    }
    if (cJSON_IsString(a) && cJSON_IsString(b))
    {
        return strcmp(a->valuestring, b->valuestring) == 0;
    }
    if (cJSON_IsNumber(a) && cJSON_IsNumber(b))
    {
        return !(a->valuedouble < b->valuedouble) && !(a->valuedouble > b->valuedouble);
    }
    return 0;
}

static const char *const k_schema_keywords[] = {"$schema",  "$id",        "title",
                                                "$defs",    "type",       "enum",
                                                "required", "properties", "additionalProperties",
                                                "items",    "minItems",   "maxItems",
                                                "minimum",  "maximum",    "$ref"};

/* 1 when v satisfies schema s (root: the document holding $defs); else 0 with f set. A schema
 * and a JSON value are trees, so the check recurses along them. */
// NOLINTNEXTLINE(misc-no-recursion)
static int schema_check(const cJSON *root, const cJSON *s, const cJSON *v, const char *where,
                        schema_fail_t *f)
{
    for (const cJSON *k = s->child; k != NULL; k = k->next)
    {
        size_t i = 0;
        while (i < sizeof(k_schema_keywords) / sizeof(k_schema_keywords[0]) &&
               strcmp(k->string, k_schema_keywords[i]) != 0)
        {
            ++i;
        }
        if (i == sizeof(k_schema_keywords) / sizeof(k_schema_keywords[0]))
        {
            return schema_fail(f, where,
                               "the schema uses a keyword this check does not know: ", k->string);
        }
    }
    const cJSON *ref = cJSON_GetObjectItemCaseSensitive(s, "$ref");
    if (ref != NULL)
    {
        const char *p = ref->valuestring;
        if (p == NULL || strncmp(p, "#/$defs/", 8) != 0)
        {
            return schema_fail(f, where, "unsupported $ref ", p);
        }
        const cJSON *target = cJSON_GetObjectItemCaseSensitive(
            cJSON_GetObjectItemCaseSensitive(root, "$defs"), p + 8);
        if (target == NULL)
        {
            return schema_fail(f, where, "unknown $ref ", p);
        }
        return schema_check(root, target, v, where, f);
    }
    const cJSON *type = cJSON_GetObjectItemCaseSensitive(s, "type");
    if (type != NULL)
    {
        int ok = 0;
        if (cJSON_IsString(type))
        {
            ok = schema_type_is(v, type->valuestring) == 1;
        }
        for (const cJSON *t = cJSON_IsArray(type) ? type->child : NULL; t != NULL && !ok;
             t = t->next)
        {
            ok = schema_type_is(v, t->valuestring) == 1;
        }
        if (!ok)
        {
            return schema_fail(f, where, "wrong type", NULL);
        }
    }
    const cJSON *en = cJSON_GetObjectItemCaseSensitive(s, "enum");
    if (en != NULL)
    {
        int ok = 0;
        for (const cJSON *e = en->child; e != NULL && !ok; e = e->next)
        {
            ok = schema_equal(e, v);
        }
        if (!ok)
        {
            return schema_fail(f, where, "not one of the enumerated values", NULL);
        }
    }
    if (cJSON_IsNumber(v))
    {
        const cJSON *lo = cJSON_GetObjectItemCaseSensitive(s, "minimum");
        const cJSON *hi = cJSON_GetObjectItemCaseSensitive(s, "maximum");
        if ((lo != NULL && v->valuedouble < lo->valuedouble) ||
            (hi != NULL && v->valuedouble > hi->valuedouble))
        {
            return schema_fail(f, where, "out of [minimum, maximum]", NULL);
        }
    }
    if (cJSON_IsObject(v))
    {
        const cJSON *props = cJSON_GetObjectItemCaseSensitive(s, "properties");
        const cJSON *req = cJSON_GetObjectItemCaseSensitive(s, "required");
        for (const cJSON *r = req != NULL ? req->child : NULL; r != NULL; r = r->next)
        {
            if (cJSON_GetObjectItemCaseSensitive(v, r->valuestring) == NULL)
            {
                return schema_fail(f, where, "missing required member ", r->valuestring);
            }
        }
        const cJSON *extra = cJSON_GetObjectItemCaseSensitive(s, "additionalProperties");
        for (const cJSON *m = v->child; m != NULL; m = m->next)
        {
            char sub[256];
            (void)snprintf(sub, sizeof(sub), "%s/%s", where, m->string);
            const cJSON *ps = cJSON_GetObjectItemCaseSensitive(props, m->string);
            if (ps == NULL && cJSON_IsFalse(extra))
            {
                return schema_fail(f, sub, "member not in the schema", NULL);
            }
            if (ps != NULL && !schema_check(root, ps, m, sub, f))
            {
                return 0;
            }
        }
    }
    if (cJSON_IsArray(v))
    {
        const int n = cJSON_GetArraySize(v);
        const cJSON *mn = cJSON_GetObjectItemCaseSensitive(s, "minItems");
        const cJSON *mx = cJSON_GetObjectItemCaseSensitive(s, "maxItems");
        if ((mn != NULL && n < mn->valueint) || (mx != NULL && n > mx->valueint))
        {
            return schema_fail(f, where, "wrong number of items", NULL);
        }
        const cJSON *items = cJSON_GetObjectItemCaseSensitive(s, "items");
        int i = 0;
        for (const cJSON *e = items != NULL ? v->child : NULL; e != NULL; e = e->next, ++i)
        {
            char sub[256];
            (void)snprintf(sub, sizeof(sub), "%s/%d", where, i);
            if (!schema_check(root, items, e, sub, f))
            {
                return 0;
            }
        }
    }
    return 1;
}

#endif /* AENL_SCHEMA_CHECK_H */
