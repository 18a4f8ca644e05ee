/* SPDX-License-Identifier: MIT */
/* diff_folders.c: the figures of a baseline folder against a fresh run's (diff_folders.h), the
 * pytest-mpl workflow: pair by relative name, compare, show the differences side by side, and
 * refresh the baseline on request. Every file written goes through NAME.tmp and a rename. */
#include "diff_folders.h"

#include "provenance.h" /* app_json_string, app_json_number */
#include "util.h"

#include "sim/sim.h"

#include <dirent.h>
#include <errno.h>
#include <limits.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

enum { IDENTICAL, WITHIN, CHANGED, MISSING, EXTRA, UNREADABLE, STATUS_COUNT };

static const char *const status_names[STATUS_COUNT] = {
    "identical", "within_tolerance", "changed", "missing", "extra", "unreadable"};

typedef struct Entry {
    const char *name; ///< relative path, '/' separated
    int status;
    int is_png;
    AppImageDiff diff;
    char note[320];
} Entry;

typedef struct NameList {
    char **names;
    int count, capacity;
} NameList;

typedef struct Walk {
    dev_t skip_dev; ///< the report folder, never walked into (it may sit inside a compared one)
    ino_t skip_ino;
    int skip;
} Walk;

static int is_figure(const char *name)
{
    size_t n = strlen(name);
    static const char *const ext[] = {".png", ".svg", ".pdf"};
    for (int k = 0; k < 3; ++k)
        if (n > 4 && strcmp(name + n - 4, ext[k]) == 0)
            return 1;
    return 0;
}

static int is_png(const char *name)
{
    size_t n = strlen(name);
    return n > 4 && strcmp(name + n - 4, ".png") == 0;
}

static int list_add(NameList *list, const char *name)
{
    if (list->count == list->capacity) {
        int capacity = list->capacity ? 2 * list->capacity : 64;
        char **grown = realloc(list->names, (size_t)capacity * sizeof *grown);
        if (!grown)
            return -1;
        list->names = grown;
        list->capacity = capacity;
    }
    return (list->names[list->count] = strdup(name)) ? (list->count++, 0) : -1;
}

static void list_free(NameList *list)
{
    for (int k = 0; k < list->count; ++k)
        free(list->names[k]);
    free(list->names);
    memset(list, 0, sizeof *list);
}

/* The figures under root/rel (rel "" = root), recursively; symbolic links are not followed. */
static int walk(const char *root, const char *rel, const Walk *w, NameList *list)
{
    char dir[PATH_MAX];
    snprintf(dir, sizeof dir, "%s%s%s", root, rel[0] ? "/" : "", rel);
    DIR *d = opendir(dir);
    if (!d)
        return -1;
    int rc = 0;
    for (struct dirent *e; rc == 0 && (e = readdir(d));) {
        if (e->d_name[0] == '.')
            continue; /* ., .. and hidden files */
        char path[PATH_MAX], sub[PATH_MAX];
        if (snprintf(path, sizeof path, "%s/%s", dir, e->d_name) >= (int)sizeof path ||
            snprintf(sub, sizeof sub, "%s%s%s", rel, rel[0] ? "/" : "", e->d_name) >=
                (int)sizeof sub) {
            rc = -1;
            break;
        }
        struct stat st;
        if (lstat(path, &st) != 0)
            rc = -1;
        else if (S_ISDIR(st.st_mode) &&
                 !(w->skip && st.st_dev == w->skip_dev && st.st_ino == w->skip_ino))
            rc = walk(root, sub, w, list);
        else if (S_ISREG(st.st_mode) && is_figure(e->d_name))
            rc = list_add(list, sub);
    }
    closedir(d);
    return rc;
}

static int compare_names(const void *a, const void *b)
{
    return strcmp(*(char *const *)a, *(char *const *)b);
}

/* 1 when the two files hold the same bytes, 0 when not, -1 when one cannot be read. */
static int same_bytes(const char *a, const char *b)
{
    FILE *fa = sim_open_input(a, NULL), *fb = sim_open_input(b, NULL);
    int same = fa && fb ? 1 : -1;
    while (same == 1) {
        char ba[8192], bb[8192];
        size_t na = fread(ba, 1, sizeof ba, fa), nb = fread(bb, 1, sizeof bb, fb);
        if (na != nb || memcmp(ba, bb, na) != 0)
            same = 0;
        else if (na == 0)
            break;
    }
    if (same >= 0 && (ferror(fa) || ferror(fb)))
        same = -1;
    if (fa)
        fclose(fa);
    if (fb)
        fclose(fb);
    return same;
}

/* mkdir -p of the folder holding path. */
static int make_parent(const char *path)
{
    char dir[PATH_MAX];
    snprintf(dir, sizeof dir, "%s", path);
    char *slash = strrchr(dir, '/');
    if (!slash || slash == dir)
        return 0;
    *slash = '\0';
    return app_make_dirs(dir);
}

/* Copies src to dst through dst.tmp and a rename, making dst's folder. 0, or -1. */
static int copy_atomic(const char *src, const char *dst)
{
    FILE *in = sim_open_input(src, NULL);
    FILE *out = in && make_parent(dst) == 0 ? app_tmp_open(dst, NULL) : NULL;
    int ok = out != NULL;
    char buffer[65536];
    for (size_t n; ok && (n = fread(buffer, 1, sizeof buffer, in)) > 0;)
        ok = fwrite(buffer, 1, n, out) == n;
    ok = ok && !ferror(in);
    if (in)
        fclose(in);
    if (!ok) {
        app_tmp_discard(&out, dst);
        return -1;
    }
    return app_tmp_commit(&out, dst);
}

static void join(char *out, size_t size, const char *a, const char *b, const char *c)
{
    snprintf(out, size, "%s/%s%s%s", a, b, c ? "/" : "", c ? c : "");
}

/* One pair: bytes first (a deterministic figure is the same file), then the image diff, which
 * draws PDFs and SVGs (their metadata is no difference) or says that it cannot. */
static void compare_pair(const char *baseline, const char *fresh, const AppFolderDiff *o, Entry *e)
{
    char a[PATH_MAX], b[PATH_MAX], d[PATH_MAX];
    join(a, sizeof a, baseline, e->name, NULL);
    join(b, sizeof b, fresh, e->name, NULL);
    int same = same_bytes(a, b);
    if (same != 0 || !o->compare) {
        e->status = same == 1 ? IDENTICAL : same == 0 ? CHANGED : UNREADABLE;
        if (same < 0) /* the name is in the entry: the note says which side */
            snprintf(e->note, sizeof e->note, "cannot read the %s file",
                     access(a, R_OK) != 0 ? "baseline" : "fresh");
        else if (same == 0)
            snprintf(e->note, sizeof e->note, "the bytes differ");
        return;
    }
    const char *diff_png = NULL;
    if (o->report_dir && e->is_png) { /* the report shows a difference image of PNGs */
        join(d, sizeof d, o->report_dir, "diff", e->name);
        diff_png = make_parent(d) == 0 ? d : NULL;
    }
    int v = o->compare(o->context, a, b, diff_png, &e->diff, e->note, sizeof e->note);
    if (v < 0) { /* no pixels of this format in this build: its bytes decide */
        char why[sizeof e->note];
        memcpy(why, e->note, sizeof why);
        snprintf(e->note, sizeof e->note, "the bytes differ (%.280s)", why);
        e->status = CHANGED;
        return;
    }
    e->status = v == 0 ? WITHIN : v == 1 ? CHANGED : UNREADABLE;
    if (v == 0) {
        e->note[0] = '\0';
        if (diff_png)
            remove(diff_png);
    }
}

/* Both sorted lists merged into entries: missing (baseline only), extra (fresh only), pairs. */
static Entry *pair_up(const NameList *base, const NameList *fresh, int *count)
{
    Entry *entries = calloc((size_t)(base->count + fresh->count) + 1, sizeof *entries);
    if (!entries)
        return NULL;
    int i = 0, j = 0, n = 0;
    while (i < base->count || j < fresh->count) {
        int c = i == base->count    ? 1
                : j == fresh->count ? -1
                                    : strcmp(base->names[i], fresh->names[j]);
        Entry *e = &entries[n++];
        e->name = c <= 0 ? base->names[i] : fresh->names[j];
        e->is_png = is_png(e->name);
        e->status = c < 0 ? MISSING : c > 0 ? EXTRA : IDENTICAL;
        i += c <= 0;
        j += c >= 0;
    }
    *count = n;
    return entries;
}

/* ---------------------------------------------------------------- the report */

static void html_text(FILE *f, const char *s)
{
    for (; *s; ++s)
        if (*s == '<')
            fputs("&lt;", f);
        else if (*s == '>')
            fputs("&gt;", f);
        else if (*s == '&')
            fputs("&amp;", f);
        else if (*s == '"')
            fputs("&quot;", f);
        else
            fputc(*s, f);
}

/* A relative URL: path characters kept, the rest percent-encoded. */
static void html_url(FILE *f, const char *folder, const char *name)
{
    fprintf(f, "%s/", folder);
    for (const unsigned char *s = (const unsigned char *)name; *s; ++s)
        if ((*s >= 'a' && *s <= 'z') || (*s >= 'A' && *s <= 'Z') || (*s >= '0' && *s <= '9') ||
            strchr("/._-", *s))
            fputc(*s, f);
        else
            fprintf(f, "%%%02X", *s);
}

static void html_cell(FILE *f, const char *folder, const char *name, int present)
{
    fputs("<td>", f);
    if (!present) {
        fputs("<span class=\"none\">none</span>", f);
    } else if (strlen(name) > 4 && strcmp(name + strlen(name) - 4, ".pdf") == 0) {
        fputs("<a href=\"", f);
        html_url(f, folder, name);
        fputs("\">PDF</a>", f);
    } else {
        fputs("<a href=\"", f);
        html_url(f, folder, name);
        fputs("\"><img src=\"", f);
        html_url(f, folder, name);
        fputs("\" alt=\"\"></a>", f);
    }
    fputs("</td>", f);
}

static void html_entry(FILE *f, const Entry *e)
{
    fprintf(f, "<tr class=\"%s\"><th>", status_names[e->status]);
    html_text(f, e->name);
    fprintf(f, "<br><span class=\"status\">%s</span>", status_names[e->status]);
    if (e->note[0]) {
        fputs("<br>", f);
        html_text(f, e->note);
    }
    fputs("</th>", f);
    html_cell(f, "baseline", e->name, e->status != EXTRA);
    html_cell(f, "fresh", e->name, e->status != MISSING);
    html_cell(f, "diff", e->name, e->status == CHANGED && e->is_png && e->diff.width > 0);
    fputs("</tr>\n", f);
}

static int write_html(const char *path, const char *baseline, const char *fresh,
                      const Entry *entries, int n, const int *counts)
{
    FILE *f = app_tmp_open(path, "<!DOCTYPE html>\n<html><head><meta charset=\"utf-8\">");
    if (!f)
        return -1;
    fputs("<title>sablier diff</title><style>\n"
          "body{font-family:sans-serif;margin:1em}table{border-collapse:collapse}\n"
          "td,th{border:1px solid #ccc;padding:4px;vertical-align:top;text-align:left}\n"
          "img{max-width:32vw;max-height:60vh}.status{font-weight:bold}.none{color:#888}\n"
          "tr.changed .status,tr.unreadable .status{color:#c00}"
          "tr.missing .status,tr.extra .status{color:#d60}\n"
          "</style></head><body>\n<h1>sablier diff</h1>\n<p>baseline <code>",
          f);
    html_text(f, baseline);
    fputs("</code>, fresh <code>", f);
    html_text(f, fresh);
    fputs("</code></p>\n<p>", f);
    for (int s = 0; s < STATUS_COUNT; ++s)
        fprintf(f, "%s%s %d", s ? ", " : "", status_names[s], counts[s]);
    fputs("</p>\n<table>\n<tr><th>figure</th><th>baseline</th><th>fresh</th>"
          "<th>difference (red: differs, orange: within the shift, yellow: under the "
          "threshold)</th></tr>\n",
          f);
    for (int k = 0; k < n; ++k)
        if (entries[k].status >= CHANGED)
            html_entry(f, &entries[k]);
    fputs("</table>\n<h2>matching</h2>\n<ul>\n", f);
    for (int k = 0; k < n; ++k)
        if (entries[k].status < CHANGED) {
            fputs("<li>", f);
            html_text(f, entries[k].name);
            fprintf(f, " (%s)</li>\n", status_names[entries[k].status]);
        }
    fputs("</ul>\n</body></html>\n", f);
    return app_tmp_commit(&f, path);
}

static void json_entry(FILE *f, const Entry *e, int last)
{
    char name[2 * PATH_MAX], note[2 * sizeof e->note], rms[32];
    app_json_string(name, sizeof name, e->name);
    app_json_string(note, sizeof note, e->note);
    fprintf(f, "    {\"name\": %s, \"status\": \"%s\"", name, status_names[e->status]);
    if (e->is_png && (e->status == WITHIN || e->status == CHANGED) && e->diff.width > 0) {
        app_json_number(rms, sizeof rms, e->diff.rms);
        fprintf(f,
                ", \"width\": %d, \"height\": %d, \"differing_pixels\": %ld, \"raw_pixels\": %ld, "
                "\"max_channel_diff\": %d, \"rms\": %s",
                e->diff.width, e->diff.height, e->diff.differing_pixels, e->diff.raw_pixels,
                e->diff.max_channel_diff, rms);
    }
    if (e->note[0])
        fprintf(f, ", \"note\": %s", note);
    fprintf(f, "}%s\n", last ? "" : ",");
}

static int write_json(const char *path, const char *baseline, const char *fresh,
                      const AppFolderDiff *o, const Entry *entries, int n, const int *counts,
                      int status)
{
    FILE *f = app_tmp_open(path, "{");
    if (!f)
        return -1;
    char a[2 * PATH_MAX], b[2 * PATH_MAX];
    app_json_string(a, sizeof a, baseline);
    app_json_string(b, sizeof b, fresh);
    fprintf(f, "  \"result\": \"%s\",\n  \"baseline\": %s,\n  \"fresh\": %s,\n",
            status == 0 ? "match" : "differ", a, b);
    fprintf(f, "  \"options\": {\"threshold\": %d, \"shift\": %d, \"max_pixels\": %ld},\n",
            o->threshold, o->shift, o->max_pixels);
    fputs("  \"counts\": {", f);
    for (int s = 0; s < STATUS_COUNT; ++s)
        fprintf(f, "%s\"%s\": %d", s ? ", " : "", status_names[s], counts[s]);
    fprintf(f, "},\n  \"figures\": [\n");
    for (int k = 0; k < n; ++k)
        json_entry(f, &entries[k], k == n - 1);
    fputs("  ]\n}\n", f);
    return app_tmp_commit(&f, path);
}

/* index.html, report.json, and copies of the figures the page shows. */
static int write_report(const char *baseline, const char *fresh, const AppFolderDiff *o,
                        const Entry *entries, int n, const int *counts, int status)
{
    const char *dir = o->report_dir;
    char src[PATH_MAX], dst[PATH_MAX];
    for (int k = 0; k < n; ++k) {
        const Entry *e = &entries[k];
        if (e->status < CHANGED)
            continue;
        join(src, sizeof src, baseline, e->name, NULL);
        join(dst, sizeof dst, dir, "baseline", e->name);
        if (e->status != EXTRA && copy_atomic(src, dst) != 0 && e->status != UNREADABLE)
            return -1;
        join(src, sizeof src, fresh, e->name, NULL);
        join(dst, sizeof dst, dir, "fresh", e->name);
        if (e->status != MISSING && copy_atomic(src, dst) != 0 && e->status != UNREADABLE)
            return -1;
    }
    char html[PATH_MAX], json[PATH_MAX];
    join(html, sizeof html, dir, "index.html", NULL);
    join(json, sizeof json, dir, "report.json", NULL);
    if (write_html(html, baseline, fresh, entries, n, counts) != 0 ||
        write_json(json, baseline, fresh, o, entries, n, counts, status) != 0)
        return -1;
    return 0;
}

/* ---------------------------------------------------------------- the command */

/* The baseline becomes the fresh figures: changed and extra ones copied, missing ones removed. */
static int update_baseline(const char *baseline, const char *fresh, const Entry *entries, int n)
{
    int written = 0, removed = 0;
    char src[PATH_MAX], dst[PATH_MAX];
    for (int k = 0; k < n; ++k) {
        const Entry *e = &entries[k];
        join(dst, sizeof dst, baseline, e->name, NULL);
        if (e->status == MISSING) {
            if (remove(dst) != 0) {
                fprintf(stderr, "sablier: diff: cannot remove %s: %s\n", dst, strerror(errno));
                return -1;
            }
            ++removed;
        } else if (e->status >= CHANGED) {
            join(src, sizeof src, fresh, e->name, NULL);
            if (copy_atomic(src, dst) != 0) {
                fprintf(stderr, "sablier: diff: cannot write %s\n", dst);
                return -1;
            }
            ++written;
        }
    }
    printf("updated %s: %d figures written, %d removed\n", baseline, written, removed);
    return 0;
}

static void print_entry(const Entry *e)
{
    printf("%-10s %s", status_names[e->status], e->name);
    if (e->status == CHANGED && e->is_png && e->diff.width > 0 && e->diff.differing_pixels > 0)
        printf(": %ld pixels differ (max channel difference %d)", e->diff.differing_pixels,
               e->diff.max_channel_diff);
    else if (e->note[0])
        printf(": %s", e->note);
    else if (e->status == MISSING)
        printf(": in the baseline only");
    else if (e->status == EXTRA)
        printf(": in the fresh folder only");
    printf("\n");
}

/* Checks the two folders (and the report's place); fills *w with the folder not to walk. */
static int check_folders(const char *baseline, const char *fresh, const AppFolderDiff *o, Walk *w)
{
    struct stat st;
    memset(w, 0, sizeof *w);
    int found = stat(fresh, &st) == 0;
    if (!found || !S_ISDIR(st.st_mode)) {
        fprintf(stderr, "sablier: diff: %s: %s\n", fresh,
                found ? "not a folder" : "no such folder");
        return -1;
    }
    found = stat(baseline, &st) == 0;
    if (found ? !S_ISDIR(st.st_mode) : !o->update) { /* --update makes a new baseline */
        fprintf(stderr, "sablier: diff: %s: %s\n", baseline,
                found ? "not a folder" : "no such folder");
        return -1;
    }
    if (o->report_dir && app_make_dirs(o->report_dir) != 0) {
        fprintf(stderr, "sablier: diff: --report %s: cannot make that folder\n", o->report_dir);
        return -1;
    }
    if (o->report_dir && stat(o->report_dir, &st) == 0) {
        w->skip = 1;
        w->skip_dev = st.st_dev;
        w->skip_ino = st.st_ino;
    }
    return 0;
}

static int list_figures(const char *root, const Walk *w, NameList *list)
{
    struct stat st;
    if (stat(root, &st) != 0)
        return 0; /* a baseline that --update will make */
    if (walk(root, "", w, list) != 0) {
        fprintf(stderr, "sablier: diff: cannot read the folder %s\n", root);
        return -1;
    }
    if (list->count > 1)
        qsort(list->names, (size_t)list->count, sizeof *list->names, compare_names);
    return 0;
}

int app_diff_folders(const char *baseline, const char *fresh, const AppFolderDiff *o)
{
    Walk w;
    NameList base = {0}, new = {0};
    if (check_folders(baseline, fresh, o, &w) != 0 || list_figures(baseline, &w, &base) != 0 ||
        list_figures(fresh, &w, &new) != 0) {
        list_free(&base);
        list_free(&new);
        return 2;
    }
    int n = 0, counts[STATUS_COUNT] = {0};
    Entry *entries = pair_up(&base, &new, &n);
    int status = entries ? 0 : 2, report_failed = 0;
    for (int k = 0; k < n; ++k) {
        Entry *e = &entries[k];
        if (e->status == IDENTICAL)
            compare_pair(baseline, fresh, o, e);
        ++counts[e->status];
        if (e->status >= CHANGED)
            print_entry(e);
        if (e->status == UNREADABLE)
            status = 2;
        else if (e->status >= CHANGED && status == 0)
            status = 1;
    }
    if (entries) {
        printf("diff: %d figures: %d identical, %d within tolerance, %d changed, %d missing, %d "
               "extra, %d unreadable\n",
               n, counts[IDENTICAL], counts[WITHIN], counts[CHANGED], counts[MISSING],
               counts[EXTRA], counts[UNREADABLE]);
        if (o->report_dir) {
            if (write_report(baseline, fresh, o, entries, n, counts, status) != 0) {
                fprintf(stderr, "sablier: diff: cannot write the report in %s\n", o->report_dir);
                status = 2;
                report_failed = 1;
            } else {
                printf("report: %s/index.html, %s/report.json\n", o->report_dir, o->report_dir);
            }
        }
    } else {
        fprintf(stderr, "sablier: diff: out of memory\n");
    }
    /* an unreadable baseline figure is replaced too; a failed report stops the update */
    if (entries && o->update && !report_failed)
        status = update_baseline(baseline, fresh, entries, n) == 0 ? 0 : 2;
    free(entries);
    list_free(&base);
    list_free(&new);
    return status;
}
