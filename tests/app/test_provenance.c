/* SPDX-License-Identifier: MIT */
/* Provenance: SHA-256 against the FIPS 180-4 examples, and the manifest that lets a run remove
 * only what an earlier run into its folder wrote. */
#include "test.h"

#include "base/util.h"
#include "output/provenance.h"

#include <stdint.h>
#include <sys/stat.h>
#include <unistd.h>

static void hex(const uint8_t d[32], char out[65])
{
    for (int k = 0; k < 32; ++k)
        snprintf(out + 2 * k, 3, "%02x", d[k]);
}

static int sha(const char *text, const char *expected)
{
    uint8_t d[32];
    char h[65];
    app_sha256(text, strlen(text), d);
    hex(d, h);
    if (strcmp(h, expected) != 0) {
        fprintf(stderr, "sha256(\"%s\") = %s, expected %s\n", text, h, expected);
        return 1;
    }
    return 0;
}

/* FIPS 180-4 / NIST CSVS examples: one block, empty, two blocks (448 bits), and a million 'a'. */
static int sha256_vectors(void)
{
    TEST_ASSERT(sha("abc", "ba7816bf8f01cfea414140de5dae2223b00361a396177a9cb410ff61f20015ad") ==
                0);
    TEST_ASSERT(sha("", "e3b0c44298fc1c149afbf4c8996fb92427ae41e4649b934ca495991b7852b855") == 0);
    TEST_ASSERT(sha("abcdbcdecdefdefgefghfghighijhijkijkljklmklmnlmnomnopnopq",
                    "248d6a61d20638b8e5c026930c3e6039a33ce45964ff2167f6ecedd419db06c1") == 0);
    char *million = malloc(1000001);
    TEST_ASSERT(million);
    memset(million, 'a', 1000000);
    million[1000000] = '\0';
    int rc = sha(million, "cdc76e5c9914fb9281a1c7e284d73e67f1809a48a497200e046d39ccc7112cd0");
    free(million);
    TEST_ASSERT(rc == 0);
    return 0;
}

static int touch(const char *path)
{
    FILE *f = fopen(path, "w");
    if (!f)
        return -1;
    fputs("x\n", f);
    return fclose(f);
}

/* The manifest lists the files the run wrote; the next run removes those (but the kept ones),
 * never a path outside the folder, never through a link to a folder elsewhere, never a link. */
static int manifest_removes_only_listed_files(void)
{
    char dir[] = "/tmp/sablier-test-manifest-XXXXXX", path[256], outside[256], away[256];
    TEST_ASSERT(mkdtemp(dir));
    snprintf(outside, sizeof outside, "%s.outside", dir);
    TEST_ASSERT(touch(outside) == 0);
    const char *names[] = {"a.csv", "sub/b.state", "keep.state"};
    snprintf(path, sizeof path, "%s/sub", dir);
    TEST_ASSERT(mkdir(path, 0777) == 0);
    for (int k = 0; k < 3; ++k) {
        snprintf(path, sizeof path, "%s/%s", dir, names[k]);
        TEST_ASSERT(app_write_atomic(path, "x\n") == 0); /* noted as the run's */
    }
    TEST_ASSERT(app_manifest_write(dir, 0) == 0);
    snprintf(path, sizeof path, "%s/manifest.txt", dir);
    FILE *f = fopen(path, "a"); /* hostile lines must not reach outside the folder */
    TEST_ASSERT(f);
    const char *base = strrchr(outside, '/') + 1;
    fprintf(f, "../%s\n/%s\naway/%s\nlink\n", base, outside, base);
    fclose(f);
    snprintf(away, sizeof away, "%s/away", dir); /* a link to the folder above */
    TEST_ASSERT(symlink("..", away) == 0);
    char link[256];
    snprintf(link, sizeof link, "%s/link", dir); /* a listed link to a file outside */
    TEST_ASSERT(symlink(outside, link) == 0);
    char keep[256], err[512] = "";
    snprintf(keep, sizeof keep, "%s/keep.state", dir);
    const char *keeps[] = {keep};
    TEST_ASSERT(app_manifest_remove_stale(dir, keeps, 1, err, sizeof err) == 2);
    snprintf(path, sizeof path, "%s/a.csv", dir);
    TEST_ASSERT(access(path, F_OK) != 0);
    snprintf(path, sizeof path, "%s/sub/b.state", dir);
    TEST_ASSERT(access(path, F_OK) != 0);
    TEST_ASSERT(access(keep, F_OK) == 0);
    TEST_ASSERT(access(outside, F_OK) == 0);
    TEST_ASSERT(access(link, F_OK) == 0);
    snprintf(path, sizeof path, "%s/manifest.txt", dir);
    TEST_ASSERT(access(path, F_OK) != 0);
    unlink(keep);
    unlink(link);
    unlink(away);
    unlink(outside);
    snprintf(path, sizeof path, "%s/sub", dir);
    rmdir(path);
    rmdir(dir);
    return 0;
}

/* A file the run did not write is not the run's, whatever its modification time: not listed. */
static int manifest_lists_files_of_this_run_only(void)
{
    char dir[] = "/tmp/sablier-test-manifest-XXXXXX", path[256], own[256];
    TEST_ASSERT(mkdtemp(dir));
    snprintf(path, sizeof path, "%s/user.csv", dir);
    TEST_ASSERT(touch(path) == 0); /* written now, by someone else */
    snprintf(own, sizeof own, "%s/own.csv", dir);
    TEST_ASSERT(app_write_atomic(own, "x\n") == 0);
    TEST_ASSERT(app_manifest_write(dir, 0) == 0);
    snprintf(path, sizeof path, "%s/manifest.txt", dir);
    FILE *f = fopen(path, "r");
    TEST_ASSERT(f);
    char line[64];
    TEST_ASSERT(fgets(line, sizeof line, f) && strcmp(line, "own.csv\n") == 0);
    TEST_ASSERT(fgets(line, sizeof line, f) == NULL); /* nothing else */
    fclose(f);
    unlink(path);
    unlink(own);
    snprintf(path, sizeof path, "%s/user.csv", dir);
    unlink(path);
    rmdir(dir);
    return 0;
}

TEST_MAIN(TEST_CASE(sha256_vectors), TEST_CASE(manifest_removes_only_listed_files),
          TEST_CASE(manifest_lists_files_of_this_run_only))
