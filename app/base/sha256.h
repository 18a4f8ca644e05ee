/* SPDX-License-Identifier: MIT */
/* sha256.h: SHA-256 (FIPS 180-4), of the scene file at load (Scene.sha256) and of the outputs'
 * provenance (app/output/provenance.h). */
#ifndef APP_SHA256_H
#define APP_SHA256_H

#include <stddef.h>
#include <stdint.h>

/// SHA-256 (FIPS 180-4) of n bytes.
void app_sha256(const void *data, size_t n, uint8_t digest[32]);
/// SHA-256 of a file as 64 lowercase hex digits. 0, or -1 when it cannot be read.
int app_sha256_file(const char *path, char hex[65]);

#endif
