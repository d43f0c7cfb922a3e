/* SPDX-License-Identifier: MIT */
/**
 * @file aenl_test_device.h
 * @brief A private twin of /dev/null for the output writer's device tests run as root, so that
 *        a regression that replaced its target could not replace the system's /dev/null.
 *        The including source defines _DEFAULT_SOURCE (mknod, makedev) before any include.
 */
#ifndef AENL_TEST_DEVICE_H
#define AENL_TEST_DEVICE_H

#include <fcntl.h>
#include <stdio.h>
#include <sys/stat.h>
#include <sys/sysmacros.h>
#include <unistd.h>

#include "unity.h"

/** The device the case writes to: as root a character device (1, 3) made at own, else
 *  /dev/null (whose folder a regression could not write as another user). Where root cannot
 *  make or open one (no mknod capability, a nodev file system) the calling test is ignored,
 *  rather than run on the system's device. */
static inline const char *aenl_test_null_device(const char *own)
{
    if (geteuid() != 0)
    {
        return "/dev/null";
    }
    (void)remove(own);
    const int fd = mknod(own, S_IFCHR | 0666, makedev(1, 3)) == 0 ? open(own, O_WRONLY) : -1;
    if (fd < 0)
    {
        (void)remove(own);
        TEST_IGNORE_MESSAGE("no private device node here (mknod or its open refused)");
    }
    (void)close(fd);
    return own;
}

#endif /* AENL_TEST_DEVICE_H */
