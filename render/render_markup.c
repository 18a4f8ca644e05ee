/* SPDX-License-Identifier: MIT */
/* render_markup.c: the plots' small text markup (docs/figures.md#markup): sub- and superscripts
 * drawn smaller and lowered or raised, Greek letters and a few symbols as UTF-8, with Cairo. A
 * string is laid out as runs of one size and baseline shift, then measured or drawn. */
#include "render_cairo_util.h"

#include <ctype.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

enum { MAX_RUNS = 48, RUN_BYTES = 64 };

typedef struct Run {
    char text[RUN_BYTES];
    double x, dy, size; /* start, baseline shift (y down), font size; pixels */
} Run;

typedef struct Markup {
    Run run[MAX_RUNS];
    int n, open;
    double x, width, above, below;
    double min_script; /* render_markup_min_script, pixels (0 = none) */
    cairo_t *cr;
} Markup;

static const cairo_user_data_key_t min_script_key;

static const char *const symbols[][2] = {
    {"alpha", "\xce\xb1"},      {"beta", "\xce\xb2"},     {"gamma", "\xce\xb3"},
    {"delta", "\xce\xb4"},      {"epsilon", "\xce\xb5"},  {"zeta", "\xce\xb6"},
    {"eta", "\xce\xb7"},        {"theta", "\xce\xb8"},    {"kappa", "\xce\xba"},
    {"lambda", "\xce\xbb"},     {"mu", "\xce\xbc"},       {"nu", "\xce\xbd"},
    {"xi", "\xce\xbe"},         {"pi", "\xcf\x80"},       {"rho", "\xcf\x81"},
    {"sigma", "\xcf\x83"},      {"tau", "\xcf\x84"},      {"phi", "\xcf\x86"},
    {"chi", "\xcf\x87"},        {"psi", "\xcf\x88"},      {"omega", "\xcf\x89"},
    {"Gamma", "\xce\x93"},      {"Delta", "\xce\x94"},    {"Theta", "\xce\x98"},
    {"Lambda", "\xce\x9b"},     {"Xi", "\xce\x9e"},       {"Pi", "\xce\xa0"},
    {"Sigma", "\xce\xa3"},      {"Phi", "\xce\xa6"},      {"Psi", "\xce\xa8"},
    {"Omega", "\xce\xa9"},      {"sqrt", "\xe2\x88\x9a"}, {"times", "\xc3\x97"},
    {"cdot", "\xc2\xb7"},       {"pm", "\xc2\xb1"},       {"langle", "\xe2\x9f\xa8"},
    {"rangle", "\xe2\x9f\xa9"}, {"deg", "\xc2\xb0"},
};

/* Closes the open run: measures it, moves the cursor past it, grows the ink box. */
static void flush(Markup *m)
{
    if (!m->open)
        return;
    Run *r = &m->run[m->n - 1];
    cairo_text_extents_t e;
    cairo_set_font_size(m->cr, r->size);
    cairo_text_extents(m->cr, r->text, &e);
    m->x = r->x + e.x_advance;
    m->width = fmax(m->width, m->x);
    if (e.width > 0 && e.height > 0) {
        m->above = fmax(m->above, -(r->dy + e.y_bearing));
        m->below = fmax(m->below, r->dy + e.y_bearing + e.height);
    }
    m->open = 0;
}

static void append(Markup *m, const char *utf8, double size, double dy)
{
    Run *r = m->open ? &m->run[m->n - 1] : NULL;
    if (!r || r->size != size || r->dy != dy || strlen(r->text) + strlen(utf8) >= RUN_BYTES) {
        flush(m);
        if (m->n == MAX_RUNS)
            return; /* a label this long is cut */
        r = &m->run[m->n++];
        *r = (Run){.x = m->x, .dy = dy, .size = size};
        m->open = 1;
    }
    strcat(r->text, utf8);
}

/* One token at *s: an escaped character, a \command (its symbol; unknown ones stay as
 * written; a space after it is kept, unlike TeX) or one UTF-8 character. */
static void token(const char **s, char out[16])
{
    const char *p = *s;
    size_t n = 1;
    if (*p == '\\' && p[1] && !isalpha((unsigned char)p[1])) {
        out[0] = p[1];
        out[1] = '\0';
        *s = p + 2;
        return;
    }
    if (*p == '\\' && p[1]) {
        const char *q = p + 1;
        while (isalpha((unsigned char)*q))
            ++q;
        size_t len = (size_t)(q - p - 1);
        for (size_t k = 0; k < sizeof symbols / sizeof symbols[0]; ++k)
            if (strlen(symbols[k][0]) == len && strncmp(symbols[k][0], p + 1, len) == 0) {
                strcpy(out, symbols[k][1]);
                *s = q; /* the space after it stays: "\phi (y)" is "φ (y)" */
                return;
            }
        n = len + 1 < 15 ? len + 1 : 15;
    } else {
        while (n < 4 && (p[n] & 0xc0) == 0x80)
            ++n;
    }
    memcpy(out, p, n);
    out[n] = '\0';
    *s = p + n;
}

/* A ^ or _ at s starts a script when a {group} follows, or one character (a \command) that
 * ends a word: v_x, t_0), rho_I/rho, x^2. Else (crater_quick, bne.gamma_x) it is written. */
static int is_script(const char *s)
{
    if (s[1] == '{')
        return 1;
    if (s[1] == '\\' && isalpha((unsigned char)s[2]))
        return 1;
    if (!s[1] || s[1] == ' ')
        return 0;
    const char *q = s + 2;
    while ((*q & 0xc0) == 0x80) /* the rest of a UTF-8 character */
        ++q;
    return !isalnum((unsigned char)*q);
}

static void group(Markup *m, const char **s, double size, double dy, int depth, int braced);

/* A script after ^ or _ at *s (its marker): one token or a {group}. */
static void script(Markup *m, const char **s, double size, double dy, int depth)
{
    char c = **s;
    ++*s;
    double small = depth < 2 ? 0.7 * size : size;
    small = fmin(size, fmax(small, m->min_script)); /* readable at print size */
    double shift = dy + (c == '^' ? -0.42 * size : 0.22 * size);
    if (**s == '{') {
        ++*s;
        group(m, s, small, shift, depth + 1, 1);
    } else if (**s) {
        char t[16];
        token(s, t);
        append(m, t, small, shift);
    }
}

static void group(Markup *m, const char **s, double size, double dy, int depth, int braced)
{
    while (**s) {
        char c = **s;
        if (c == '}') {
            ++*s;
            if (braced)
                return;
        } else if (c == '{') {
            ++*s;
            group(m, s, size, dy, depth, 1);
        } else if ((c == '^' || c == '_') && is_script(*s)) {
            flush(m);
            double start = m->x;
            script(m, s, size, dy, depth);
            char other = c == '^' ? '_' : '^';
            if (**s == other) { /* stacked: E^*_{kin} */
                flush(m);
                double end = m->x;
                m->x = start;
                script(m, s, size, dy, depth);
                flush(m);
                m->x = fmax(m->x, end);
            }
        } else if (strncmp(*s, "\\sqrt{", 6) == 0) {
            *s += 6;
            append(m, "\xe2\x88\x9a(", size, dy);
            group(m, s, size, dy, depth, 1);
            append(m, ")", size, dy);
        } else {
            char t[16];
            token(s, t);
            append(m, t, size, dy);
        }
    }
}

static void layout(cairo_t *cr, const char *text, double size, Markup *m)
{
    memset(m, 0, sizeof *m);
    m->cr = cr;
    const double *min = cairo_get_user_data(cr, &min_script_key);
    m->min_script = min ? *min : 0.0;
    cairo_save(cr);
    const char *s = text ? text : "";
    group(m, &s, size, 0.0, 0, 0);
    flush(m);
    cairo_restore(cr);
}

void render_markup_min_script(cairo_t *cr, double size)
{
    double *min = malloc(sizeof *min);
    if (!min)
        return; /* scripts stay at 0.7 of their base */
    *min = size;
    if (cairo_set_user_data(cr, &min_script_key, min, free) != CAIRO_STATUS_SUCCESS)
        free(min);
}

void render_markup_measure(cairo_t *cr, const char *text, double size, double *width, double *above,
                           double *below)
{
    Markup m;
    layout(cr, text, size, &m);
    *width = m.width;
    *above = m.above;
    *below = m.below;
}

void render_markup_draw(cairo_t *cr, double x, double y, const char *text, double size,
                        double halign, double valign, double box[4])
{
    Markup m;
    layout(cr, text, size, &m);
    /* Anchored on the capital height (0.729 em of DejaVu Sans) like render_text_draw. */
    double x0 = x - halign * m.width, base = y + 0.729 * size * (1.0 - valign);
    cairo_save(cr);
    for (int k = 0; k < m.n; ++k) {
        cairo_set_font_size(cr, m.run[k].size);
        cairo_move_to(cr, x0 + m.run[k].x, base + m.run[k].dy);
        cairo_show_text(cr, m.run[k].text);
    }
    cairo_new_path(cr);
    cairo_restore(cr);
    if (box) {
        box[0] = x0;
        box[1] = base - m.above;
        box[2] = x0 + m.width;
        box[3] = base + m.below;
    }
}
