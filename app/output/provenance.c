/* SPDX-License-Identifier: MIT */
/* provenance.c: the provenance members of summary.json, and output-folder manifests. */
#define _XOPEN_SOURCE 700
#include "output/provenance.h"

#include "base/util.h"
#include "sim/sim.h"

#include <errno.h>
#include <fcntl.h>
#include <limits.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <sys/utsname.h>
#include <unistd.h>

/* ---------------------------------------------------------------- JSON */

void app_json_string(char *out, size_t size, const char *text)
{
    size_t n = 0;
    if (size < 3)
        return;
    out[n++] = '"';
    for (const unsigned char *c = (const unsigned char *)(text ? text : ""); *c && n + 8 < size;
         ++c) {
        if (*c == '"' || *c == '\\') {
            out[n++] = '\\';
            out[n++] = (char)*c;
        } else if (*c < 0x20) {
            n += (size_t)snprintf(out + n, size - n, "\\u%04x", *c);
        } else {
            out[n++] = (char)*c;
        }
    }
    out[n++] = '"';
    out[n] = '\0';
}

void app_json_number(char *out, size_t size, double v)
{
    if (isfinite(v))
        snprintf(out, size, "%.10g", v);
    else
        snprintf(out, size, "null");
}

/* ---------------------------------------------------------------- provenance */

/* The CPU's model name from /proc/cpuinfo (Linux), else the machine name of uname. */
static void cpu_name(char *out, size_t size)
{
    struct utsname u;
    snprintf(out, size, "%s", uname(&u) == 0 ? u.machine : "unknown");
    FILE *f = fopen("/proc/cpuinfo", "r");
    if (!f)
        return;
    char line[512];
    while (fgets(line, sizeof line, f)) {
        const char *colon = strchr(line, ':');
        if (strncmp(line, "model name", 10) == 0 && colon) {
            colon += 1 + (colon[1] == ' ');
            snprintf(out, size, "%.*s", (int)strcspn(colon, "\n"), colon);
            break;
        }
    }
    fclose(f);
}

int app_provenance_date(char *out, size_t size)
{
    const char *epoch = getenv("SOURCE_DATE_EPOCH");
    char *end = NULL;
    long long seconds = epoch && *epoch ? strtoll(epoch, &end, 10) : -1;
    int pinned = end && *end == '\0' && seconds >= 0;
    time_t now = pinned ? (time_t)seconds : time(NULL);
    struct tm tm;
    if (gmtime_r(&now, &tm))
        strftime(out, size, "%Y-%m-%dT%H:%M:%SZ", &tm);
    else
        snprintf(out, size, "unknown");
    return pinned;
}

/* `path` (absolute) inside `dir` (absolute): the rest, "." for dir itself; else NULL. */
static const char *inside(const char *path, const char *dir)
{
    size_t n = strlen(dir);
    while (n > 1 && dir[n - 1] == '/')
        --n;
    if (n == 0 || strncmp(path, dir, n) != 0 || (path[n] != '/' && path[n] != '\0'))
        return NULL;
    const char *rest = path + n;
    while (*rest == '/')
        ++rest;
    return *rest ? rest : ".";
}

void app_provenance_path(const AppProvenance *p, const char *path, char *out, size_t size)
{
    if (path[0] != '/') { /* as given */
        snprintf(out, size, "%s", path);
        return;
    }
    char out_dir[PATH_MAX], cwd[PATH_MAX], real[PATH_MAX];
    const char *target = realpath(path, real) ? real : path, *rest = NULL;
    if (p && p->out_dir && realpath(p->out_dir, out_dir))
        rest = inside(target, out_dir);
    if (!rest && getcwd(cwd, sizeof cwd))
        rest = inside(target, cwd);
    if (!rest) {
        const char *slash = strrchr(path, '/');
        rest = slash && slash[1] ? slash + 1 : ".";
    }
    snprintf(out, size, "%s", rest);
}

/* Argument k of the command line as recorded. */
static void recorded_argument(const AppProvenance *p, int k, char *out, size_t size)
{
    const char *arg = p->argv[k], *eq = strchr(arg, '=');
    if (k == 0) {
        snprintf(out, size, "sablier");
    } else if (arg[0] == '/') {
        app_provenance_path(p, arg, out, size);
    } else if (eq && eq[1] == '/') {
        int key = (int)(eq - arg + 1);
        snprintf(out, size, "%.*s", key, arg);
        size_t n = strlen(out);
        app_provenance_path(p, eq + 1, out + n, size - n);
    } else {
        snprintf(out, size, "%s", arg);
    }
}

size_t app_provenance_command(const AppProvenance *p, char *out, size_t size)
{
    size_t n = 0;
    out[0] = '\0';
    for (int k = 0; p && k < p->argc && n < size; ++k) {
        char arg[1024];
        recorded_argument(p, k, arg, sizeof arg);
        n += (size_t)snprintf(out + n, size - n, "%s%s", k ? " " : "", arg);
    }
    return n < size ? n : size - 1;
}

/* A JSON array of strings: the items, or the recorded command line when items is NULL. */
static size_t json_strings(char *out, size_t size, const AppProvenance *p, const char *const *items,
                           int count)
{
    size_t n = (size_t)snprintf(out, size, "[");
    for (int k = 0; k < count && n < size; ++k) {
        char arg[1024], item[1100];
        if (!items)
            recorded_argument(p, k, arg, sizeof arg);
        app_json_string(item, sizeof item, items ? items[k] : arg);
        n += (size_t)snprintf(out + n, size - n, "%s%s", k ? ", " : "", item);
    }
    if (n < size)
        n += (size_t)snprintf(out + n, size - n, "]");
    return n < size ? n : size - 1;
}

size_t app_provenance_json(const AppProvenance *p, const char *scene_sha256,
                           const char *resolved_name, char *out, size_t size)
{
    char command[4096], sets[4096], host[300] = "unknown", host_json[320], cpu[256], cpu_json[300],
                                    date[40], revision[120], resolved[300];
    json_strings(command, sizeof command, p, NULL, p && p->argv ? p->argc : 0);
    json_strings(sets, sizeof sets, p, p ? p->sets : NULL, p && p->sets ? p->set_count : 0);
    if (gethostname(host, sizeof host - 1) != 0)
        snprintf(host, sizeof host, "unknown");
    host[sizeof host - 1] = '\0';
    app_json_string(host_json, sizeof host_json, host);
    cpu_name(cpu, sizeof cpu);
    app_json_string(cpu_json, sizeof cpu_json, cpu);
    app_provenance_date(date, sizeof date);
    app_json_string(revision, sizeof revision,
                    p && p->revision && p->revision[0] ? p->revision : "unknown");
    app_json_string(resolved, sizeof resolved, resolved_name ? resolved_name : "");
    int n = snprintf(out, size,
                     "  \"provenance\": {\"command\": %s, \"sets\": %s, \"scene_sha256\": \"%s\", "
                     "\"resolved_scene\": %s, \"revision\": %s, \"date\": \"%s\", \"host\": %s, "
                     "\"cpu\": %s}\n",
                     command, sets, scene_sha256 ? scene_sha256 : "", resolved, revision, date,
                     host_json, cpu_json);
    return n < 0 ? 0 : (size_t)n < size ? (size_t)n : size - 1;
}

void app_provenance_comment(const AppProvenance *p, const char *scene_sha256, char *out,
                            size_t size)
{
    size_t n = (size_t)snprintf(out, size, "command: ");
    if (n < size)
        n += app_provenance_command(p, out + n, size - n);
    char date[40], cpu[256], dated[60] = "";
    if (app_provenance_date(date, sizeof date)) /* else no date: same bytes on every run */
        snprintf(dated, sizeof dated, "; date: %s", date);
    cpu_name(cpu, sizeof cpu);
    if (n < size)
        snprintf(out + n, size - n, "; scene sha256: %s; revision: %s%s; cpu: %s",
                 scene_sha256 ? scene_sha256 : "",
                 p && p->revision && p->revision[0] ? p->revision : "unknown", dated, cpu);
}

/* ---------------------------------------------------------------- manifests */

/* A manifest line is ours to remove: relative, no "..", no empty component. */
static int safe_relative(const char *rel)
{
    if (!rel[0] || rel[0] == '/')
        return 0;
    for (const char *c = rel; *c;) {
        size_t len = strcspn(c, "/");
        if (len == 0 || (len == 2 && c[0] == '.' && c[1] == '.') || (len == 1 && c[0] == '.'))
            return 0;
        c += len + (c[len] == '/');
    }
    return 1;
}

/* `path` relative to `dir` when it names a file inside dir other than the manifest, else NULL. */
static const char *manifest_entry(const char *dir, const char *path)
{
    const char *rel = inside(path, dir);
    return rel && strcmp(rel, ".") != 0 && safe_relative(rel) && strcmp(rel, "manifest.txt") != 0
               ? rel
               : NULL;
}

typedef struct Listing {
    char **paths; /* relative to the folder */
    int count, capacity, failed;
} Listing;

/* Adds `rel` when dir/rel is a regular file now (not a link: lstat). */
static void listing_add(Listing *l, const char *dir, const char *rel)
{
    char path[2 * PATH_MAX + 2];
    struct stat st;
    snprintf(path, sizeof path, "%s/%s", dir, rel);
    if (lstat(path, &st) != 0 || !S_ISREG(st.st_mode))
        return;
    if (l->count == l->capacity) {
        int capacity = l->capacity ? 2 * l->capacity : 64;
        char **grown = realloc(l->paths, (size_t)capacity * sizeof *grown);
        if (!grown) {
            l->failed = 1;
            return;
        }
        l->paths = grown;
        l->capacity = capacity;
    }
    if ((l->paths[l->count] = strdup(rel)) != NULL)
        l->count++;
    else
        l->failed = 1;
}

static int compare_paths(const void *a, const void *b)
{
    return strcmp(*(char *const *)a, *(char *const *)b);
}

int app_manifest_write(const char *dir, int keep_listed)
{
    char path[PATH_MAX], line[PATH_MAX];
    if (snprintf(path, sizeof path, "%s/manifest.txt", dir) >= (int)sizeof path)
        return -1;
    Listing l = {0};
    const char *noted, *rel;
    for (int k = 0; (noted = app_output_committed(k)) != NULL; ++k)
        if ((rel = manifest_entry(dir, noted)) != NULL)
            listing_add(&l, dir, rel);
    FILE *old = keep_listed ? sim_open_input(path, NULL) : NULL;
    while (old && fgets(line, sizeof line, old)) {
        line[strcspn(line, "\n")] = '\0';
        if (safe_relative(line) && strcmp(line, "manifest.txt") != 0)
            listing_add(&l, dir, line);
    }
    if (old)
        fclose(old);
    FILE *out = l.failed ? NULL : app_tmp_open(path, NULL);
    /* sorted, each once: the same run makes the same manifest */
    if (l.count > 0)
        qsort(l.paths, (size_t)l.count, sizeof(char *), compare_paths);
    for (int k = 0; out && k < l.count; ++k)
        if (k == 0 || strcmp(l.paths[k], l.paths[k - 1]) != 0)
            fprintf(out, "%s\n", l.paths[k]);
    for (int k = 0; k < l.count; ++k)
        free(l.paths[k]);
    free(l.paths);
    return out ? app_tmp_commit(&out, path) : -1;
}

/* 1 when the file `st` describes is one of the `keep` paths. */
static int kept(const struct stat *st, const char *const *keep, int keep_count)
{
    struct stat b;
    for (int k = 0; k < keep_count; ++k)
        if (keep[k] && stat(keep[k], &b) == 0 && st->st_dev == b.st_dev && st->st_ino == b.st_ino)
            return 1;
    return 0;
}

/* Removes dir/REL when it is a regular file reached without leaving dir: each folder on the way
 * opened with O_NOFOLLOW (a link to a folder elsewhere is never followed), the file itself looked
 * at without following a link (a link, a FIFO or a device is left alone), and not one of `keep`.
 * 1 removed, 0 left alone (absent, or not a file of ours), -1 (errno) when it cannot be removed. */
static int remove_listed(const char *dir, const char *rel, const char *const *keep, int keep_count)
{
    char part[PATH_MAX];
    int fd = open(dir, O_RDONLY | O_DIRECTORY | O_CLOEXEC);
    for (const char *c = rel; fd >= 0;) {
        size_t len = strcspn(c, "/");
        snprintf(part, sizeof part, "%.*s", (int)len, c);
        if (c[len] != '/')
            break;
        int next = openat(fd, part, O_RDONLY | O_DIRECTORY | O_NOFOLLOW | O_CLOEXEC);
        close(fd);
        fd = next;
        c += len + 1;
    }
    if (fd < 0)
        return 0; /* a folder on the way is missing, or is a link */
    struct stat st;
    int rc = 0;
    if (fstatat(fd, part, &st, AT_SYMLINK_NOFOLLOW) == 0 && S_ISREG(st.st_mode) &&
        !kept(&st, keep, keep_count))
        rc = unlinkat(fd, part, 0) == 0 ? 1 : errno == ENOENT ? 0 : -1;
    int saved = errno;
    close(fd);
    errno = saved;
    return rc;
}

int app_manifest_remove_stale(const char *dir, const char *const *keep, int keep_count, char *err,
                              size_t err_size)
{
    char manifest[PATH_MAX];
    if (snprintf(manifest, sizeof manifest, "%s/manifest.txt", dir) >= (int)sizeof manifest)
        return 0;
    FILE *f = sim_open_input(manifest, NULL);
    if (!f)
        return 0; /* nothing of ours there */
    char line[PATH_MAX];
    int removed = 0, rc = 0;
    while (fgets(line, sizeof line, f)) {
        line[strcspn(line, "\n")] = '\0';
        int gone = safe_relative(line) ? remove_listed(dir, line, keep, keep_count) : 0;
        if (gone < 0) {
            snprintf(err, err_size, "cannot remove the previous run's %s/%s: %s", dir, line,
                     strerror(errno));
            rc = -1;
            break;
        }
        removed += gone;
    }
    fclose(f);
    if (rc == 0)
        unlink(manifest);
    return rc == 0 ? removed : -1;
}
