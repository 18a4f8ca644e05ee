/* SPDX-License-Identifier: MIT */
/* diff_folders.c: the figures of a baseline folder against a fresh run's (diff_folders.h), the
 * pytest-mpl workflow: pair by relative name, compare, show the differences side by side, and
 * refresh the baseline on request. Every file written goes through NAME.tmp and a rename. */
#include "output/diff_folders.h"

#include "base/util.h"
#include "output/provenance.h" /* app_json_string, app_json_number */
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
    int shown[3]; ///< the report holds the baseline, fresh and difference image to show
    char note[320];
} Entry;

enum { BASELINE_SIDE, FRESH_SIDE, DIFF_SIDE };

static const char *const sides[3] = {"baseline", "fresh", "diff"};

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

/* The image the report shows for one side of e (dir NULL: relative to the report): the PNG
 * itself, or NAME.png, a PDF or SVG drawn as pixels (the difference image of those too). */
static void shown_path(char *out, size_t size, const char *dir, int side, const Entry *e)
{
    snprintf(out, size, "%s%s%s/%s%s", dir ? dir : "", dir ? "/" : "", sides[side], e->name,
             e->is_png ? "" : ".png");
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
    if (o->report_dir) { /* the report shows a difference image (of a PDF or SVG's pixels too) */
        shown_path(d, sizeof d, o->report_dir, DIFF_SIDE, e);
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
    if (v == 0)
        e->note[0] = '\0';
    e->shown[DIFF_SIDE] = diff_png && e->diff.width > 0; /* else none was written */
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
static void html_url(FILE *f, const char *path)
{
    for (const unsigned char *s = (const unsigned char *)path; *s; ++s)
        if ((*s >= 'a' && *s <= 'z') || (*s >= 'A' && *s <= 'Z') || (*s >= '0' && *s <= '9') ||
            strchr("/._-", *s))
            fputc(*s, f);
        else
            fprintf(f, "%%%02X", *s);
}

/* The share of pixels that differ, in [0, 1]; 0 when no pixels were compared. */
static double changed_share(const AppImageDiff *d)
{
    double n = (double)d->width * (double)d->height;
    return n > 0.0 ? (double)d->differing_pixels / n : 0.0;
}

/* The page's style and script, inline: the page needs no network and fits any window. */
static const char page_style[] =
    "*{box-sizing:border-box}body{font-family:sans-serif;margin:0;padding:1em;max-width:100%;"
    "overflow-wrap:anywhere}\n"
    "h1{margin:0 0 .3em}code,.nums{font-family:monospace}.nums{margin:.3em 0}\n"
    "#filters{border:1px solid #ccc;padding:.3em .6em;margin:.6em 0}\n"
    "#filters label{display:inline-block;margin-right:1.2em;white-space:nowrap}\n"
    ".fig{border:1px solid #ccc;border-radius:4px;margin:0 0 1em;padding:.5em;overflow:hidden}\n"
    ".fig h2{font-size:1.05em;margin:0;overflow-wrap:anywhere}.fig p{margin:.2em 0}\n"
    ".status{font-weight:bold}.changed .status,.unreadable .status{color:#c00}\n"
    ".missing .status,.extra .status{color:#d60}.within_tolerance .status{color:#880}\n"
    ".imgs{display:grid;gap:.5em;"
    "grid-template-columns:repeat(auto-fit,minmax(min(100%,16em),1fr))}\n"
    ".imgs figure{margin:0;min-width:0}.imgs figcaption{font-size:.9em;color:#444}\n"
    ".imgs img{display:block;max-width:100%;height:auto;max-height:45vh;cursor:zoom-in;"
    "border:1px solid #eee;background:#fff}\n"
    ".none{color:#888}.hide{display:none}button{margin:.2em .4em .2em 0}\n"
    "#zoom{position:fixed;inset:0;background:rgba(0,0,0,.85);display:none;overflow:auto;"
    "cursor:zoom-out;z-index:9;padding:1em}\n"
    "#zoom.on{display:block}#zoom img{display:block;margin:auto;max-width:none;background:#fff}\n";

static const char page_script[] =
    "var $=function(q,r){return Array.prototype.slice.call((r||document).querySelectorAll(q));};\n"
    "$('#filters input').forEach(function(c){c.onchange=function(){"
    "$('.fig[data-status=\"'+c.value+'\"]').forEach(function(f){"
    "f.classList.toggle('hide',!c.checked);});};});\n"
    "var zoom=document.getElementById('zoom'),big=zoom.querySelector('img');\n"
    "$('.imgs img').forEach(function(i){i.onclick=function(){big.src=i.src;"
    "zoom.classList.add('on');};});\n"
    "zoom.onclick=function(){zoom.classList.remove('on');};\n"
    "document.addEventListener('keydown',function(e){"
    "if(e.key==='Escape')zoom.classList.remove('on');});\n"
    "$('.fig').forEach(function(f){var i=f.querySelector('img.both');if(!i)return;\n"
    " var cap=f.querySelector('.side'),timer=null;\n"
    " function flip(){var s=i.dataset.side==='baseline'?'fresh':'baseline';\n"
    "  i.dataset.side=s;i.src=i.dataset[s];cap.textContent=s;}\n"
    " f.querySelector('button.flip').onclick=flip;\n"
    " f.querySelector('button.blink').onclick=function(){if(timer){clearInterval(timer);"
    "timer=null;this.textContent='blink';}else{timer=setInterval(flip,600);"
    "this.textContent='stop';}};});\n";

/* One image of a figure: side's PNG (shown 1), a link to its copy (2), or none (0). */
static void html_figure(FILE *f, const char *caption, const Entry *e, int side)
{
    char path[PATH_MAX];
    shown_path(path, sizeof path, NULL, side, e);
    fprintf(f, "<figure><figcaption>%s</figcaption>", caption);
    if (e->shown[side] == 1) {
        fputs("<img src=\"", f);
        html_url(f, path);
        fputs("\" alt=\"\" loading=\"lazy\">", f);
    } else if (e->shown[side] == 2) { /* a PDF or SVG this build cannot draw */
        join(path, sizeof path, sides[side], e->name, NULL);
        fputs("<a href=\"", f);
        html_url(f, path);
        fputs("\">", f);
        html_text(f, e->name);
        fputs("</a> (not drawn: this build has no poppler-glib or librsvg)", f);
    } else {
        fputs("<span class=\"none\">none</span>", f);
    }
    fputs("</figure>", f);
}

/* The numbers the terminal prints: max channel difference, RMS, share of changed pixels. */
static void html_numbers(FILE *f, const Entry *e)
{
    if (e->diff.width <= 0)
        return;
    char rms[32];
    snprintf(rms, sizeof rms, "%.4g", e->diff.rms);
    fprintf(f,
            "<p class=\"nums\">max difference <b class=\"max\">%d</b> &middot; RMS "
            "<b class=\"rms\">%s</b> &middot; changed <b class=\"share\">%.4g %%</b> of the "
            "pixels (%ld of %dx%d)</p>\n",
            e->diff.max_channel_diff, rms, 100.0 * changed_share(&e->diff),
            e->diff.differing_pixels, e->diff.width, e->diff.height);
}

/* One figure: name, status, numbers, baseline, fresh, difference and the blink toggle. */
static void html_entry(FILE *f, const Entry *e, int hidden)
{
    char path[3][PATH_MAX];
    for (int s = 0; s < 3; ++s)
        shown_path(path[s], sizeof path[s], NULL, s, e);
    fprintf(f, "<section class=\"fig %s%s\" data-status=\"%s\"><h2>", status_names[e->status],
            hidden ? " hide" : "", status_names[e->status]);
    html_text(f, e->name);
    fprintf(f, "</h2>\n<p><span class=\"status\">%s</span>", status_names[e->status]);
    if (e->note[0]) {
        fputs(": ", f);
        html_text(f, e->note);
    }
    fputs("</p>\n", f);
    html_numbers(f, e);
    if (!e->shown[BASELINE_SIDE] && !e->shown[FRESH_SIDE] && !e->shown[DIFF_SIDE]) {
        fputs("</section>\n", f);
        return;
    }
    int both = e->shown[BASELINE_SIDE] == 1 && e->shown[FRESH_SIDE] == 1;
    if (both)
        fputs("<p><button class=\"flip\" type=\"button\">baseline / fresh</button>"
              "<button class=\"blink\" type=\"button\">blink</button></p>\n",
              f);
    fputs("<div class=\"imgs\">", f);
    html_figure(f, "baseline", e, BASELINE_SIDE);
    html_figure(f, "fresh", e, FRESH_SIDE);
    html_figure(f,
                "difference (red: differs, orange: within the shift, yellow: under the threshold)",
                e, DIFF_SIDE);
    if (both) {
        fputs("<figure><figcaption>toggle: <span class=\"side\">baseline</span></figcaption>"
              "<img class=\"both\" alt=\"\" data-side=\"baseline\" src=\"",
              f);
        html_url(f, path[BASELINE_SIDE]);
        fputs("\" data-baseline=\"", f);
        html_url(f, path[BASELINE_SIDE]);
        fputs("\" data-fresh=\"", f);
        html_url(f, path[FRESH_SIDE]);
        fputs("\"></figure>", f);
    }
    fputs("</div>\n</section>\n", f);
}

/* The head of the page: what was compared, the options and a filter by status. */
static void html_head(FILE *f, const char *baseline, const char *fresh, const AppFolderDiff *o,
                      const int *counts)
{
    char a[PATH_MAX], b[PATH_MAX];
    app_provenance_path(NULL, baseline, a, sizeof a); /* no absolute path in the report */
    app_provenance_path(NULL, fresh, b, sizeof b);
    fprintf(f, "<title>sablier diff</title>\n<style>\n%s</style></head><body>\n", page_style);
    fputs("<h1>sablier diff</h1>\n<p>baseline <code>", f);
    html_text(f, a);
    fputs("</code>, fresh <code>", f);
    html_text(f, b);
    fprintf(f,
            "</code>; a pixel differs when a channel differs by more than %d levels and no pixel "
            "within %d matches it; a figure matches when at most %ld pixels differ</p>\n",
            o->threshold, o->shift, o->max_pixels);
    fputs("<fieldset id=\"filters\"><legend>show</legend>", f);
    for (int s = 0; s < STATUS_COUNT; ++s)
        fprintf(f, "<label><input type=\"checkbox\" value=\"%s\"%s> %s (%d)</label>",
                status_names[s], s == IDENTICAL ? "" : " checked", status_names[s], counts[s]);
    fputs("</fieldset>\n", f);
}

/* index.html: every figure, the ones that do not match first; identical ones hidden at first. */
static int write_html(const char *path, const char *baseline, const char *fresh,
                      const AppFolderDiff *o, const Entry *entries, int n, const int *counts)
{
    FILE *f = app_tmp_open(path, "<!DOCTYPE html>\n<html lang=\"en\"><head><meta charset=\"utf-8\">"
                                 "<meta name=\"viewport\" content=\"width=device-width, "
                                 "initial-scale=1\">");
    if (!f)
        return -1;
    html_head(f, baseline, fresh, o, counts);
    for (int pass = 0; pass < 2; ++pass)
        for (int k = 0; k < n; ++k)
            if ((entries[k].status >= CHANGED) == (pass == 0))
                html_entry(f, &entries[k], entries[k].status == IDENTICAL);
    fprintf(f, "<div id=\"zoom\"><img alt=\"\"></div>\n<script>\n%s</script>\n</body></html>\n",
            page_script);
    return app_tmp_commit(&f, path);
}

static void json_entry(FILE *f, const Entry *e, int last)
{
    char name[2 * PATH_MAX], note[2 * sizeof e->note], num[2][32], path[PATH_MAX],
        json_path[2 * PATH_MAX];
    app_json_string(name, sizeof name, e->name);
    app_json_string(note, sizeof note, e->note);
    fprintf(f, "    {\"name\": %s, \"status\": \"%s\"", name, status_names[e->status]);
    if ((e->status == WITHIN || e->status == CHANGED) && e->diff.width > 0) {
        app_json_number(num[0], sizeof num[0], e->diff.rms);
        app_json_number(num[1], sizeof num[1], changed_share(&e->diff));
        fprintf(f,
                ", \"width\": %d, \"height\": %d, \"differing_pixels\": %ld, \"raw_pixels\": %ld, "
                "\"max_channel_diff\": %d, \"rms\": %s, \"changed_share\": %s",
                e->diff.width, e->diff.height, e->diff.differing_pixels, e->diff.raw_pixels,
                e->diff.max_channel_diff, num[0], num[1]);
    }
    for (int s = 0; s < 3; ++s)
        if (e->shown[s] == 1) { /* the images on the page, relative to the report folder */
            shown_path(path, sizeof path, NULL, s, e);
            app_json_string(json_path, sizeof json_path, path);
            fprintf(f, ", \"%s_image\": %s", sides[s], json_path);
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
    char rel[2][PATH_MAX], a[2 * PATH_MAX], b[2 * PATH_MAX];
    app_provenance_path(NULL, baseline, rel[0], sizeof rel[0]);
    app_provenance_path(NULL, fresh, rel[1], sizeof rel[1]);
    app_json_string(a, sizeof a, rel[0]);
    app_json_string(b, sizeof b, rel[1]);
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

/* One side of a figure into the report: the copy, and for a PDF or SVG its pixels as a PNG
 * (shown 1), or a link to the copy where they cannot be drawn (shown 2). 0, or -1 when a file
 * cannot be written (an unreadable figure is shown as none). */
static int report_side(const char *root, const AppFolderDiff *o, int side, Entry *e)
{
    char src[PATH_MAX], dst[PATH_MAX], png[PATH_MAX], err[512];
    join(src, sizeof src, root, e->name, NULL);
    join(dst, sizeof dst, o->report_dir, sides[side], e->name);
    if (copy_atomic(src, dst) != 0)
        return e->status == UNREADABLE ? 0 : -1;
    if (e->is_png || !o->image) {
        e->shown[side] = e->is_png ? 1 : 2;
        return 0;
    }
    shown_path(png, sizeof png, o->report_dir, side, e);
    int rc = o->image(o->context, src, png, err, sizeof err);
    if (rc < 0)
        fprintf(stderr, "sablier: diff: %s\n", err);
    e->shown[side] = rc == 0 ? 1 : 2;
    return rc < 0 ? -1 : 0;
}

/* index.html, report.json, and copies of the figures the page shows. */
static int write_report(const char *baseline, const char *fresh, const AppFolderDiff *o,
                        Entry *entries, int n, const int *counts, int status)
{
    const char *dir = o->report_dir;
    for (int k = 0; k < n; ++k) {
        Entry *e = &entries[k];
        if (e->status == IDENTICAL)
            continue;
        if ((e->status != EXTRA && report_side(baseline, o, BASELINE_SIDE, e) != 0) ||
            (e->status != MISSING && report_side(fresh, o, FRESH_SIDE, e) != 0))
            return -1;
    }
    char html[PATH_MAX], json[PATH_MAX];
    join(html, sizeof html, dir, "index.html", NULL);
    join(json, sizeof json, dir, "report.json", NULL);
    if (write_html(html, baseline, fresh, o, entries, n, counts) != 0 ||
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
    if (e->status == CHANGED && e->diff.width > 0 && e->diff.differing_pixels > 0)
        printf(": %ld pixels differ (max channel difference %d, RMS %.4g, %.4g %% of the pixels)",
               e->diff.differing_pixels, e->diff.max_channel_diff, e->diff.rms,
               100.0 * changed_share(&e->diff));
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
