/* SPDX-License-Identifier: MIT */
/**
 * @file aenl_status.c
 * @brief Names of the status codes.
 */
#include "aenl/aenl_types.h"

const char *aenl_status_str(aenl_status_t status)
{
    switch (status)
    {
        case AENL_OK:
            return "AENL_OK";
        case AENL_E_ARG:
            return "AENL_E_ARG";
        case AENL_E_DIM:
            return "AENL_E_DIM";
        case AENL_E_EMPTY:
            return "AENL_E_EMPTY";
        case AENL_E_NOT_PD:
            return "AENL_E_NOT_PD";
        case AENL_E_NUMERIC:
            return "AENL_E_NUMERIC";
        case AENL_E_IO:
            return "AENL_E_IO";
        default:
            break;
    }
    return "AENL_E_UNKNOWN";
}
