/* SPDX-License-Identifier: MIT */
/* diff_folders.h: `sablier diff BASELINE FRESH` on two folders (docs/ci.md): the figures (PNG,
 * SVG, PDF) of both, paired by their path relative to each folder; the missing and extra ones;
 * each pair compared by the image diff the caller gives (the app core sees no renderer): PNGs,
 * and PDFs and SVGs drawn as pixels where the renderer can, else by their bytes; a summary page
 * (index.html) and report.json; --update copies the fresh figures over the baseline. */
#ifndef APP_DIFF_FOLDERS_H
#define APP_DIFF_FOLDERS_H

#include <stddef.h>

/// One PNG pair as the image diff saw it.
typedef struct AppImageDiff {
    int verdict;           ///< 0 match, 1 differ (a size change too), 2 unreadable
    long differing_pixels; ///< after the shift test
    long raw_pixels;       ///< before the shift test
    int max_channel_diff;  ///< 0-255
    double rms;            ///< channel levels
    int width, height;     ///< pixels, of the baseline; 0 when the pixels were not compared
} AppImageDiff;

/// Compares baseline and fresh figure files by their pixels; writes an image of the differences
/// to diff_png when not NULL. Returns the verdict (also in *result), with a message in err when
/// it is not 0; -1 when it cannot draw that format (err says why: the bytes decide).
typedef int (*AppImageCompare)(void *context, const char *baseline, const char *fresh,
                               const char *diff_png, AppImageDiff *result, char *err,
                               size_t err_size);

/// Draws a PDF or SVG figure as a PNG for the report page, through a temporary name and a
/// rename. 0; 1 when it cannot draw the figure (the page links it); -1 when the PNG cannot be
/// written; a message in err.
typedef int (*AppFigureImage)(void *context, const char *figure, const char *png, char *err,
                              size_t err_size);

typedef struct AppFolderDiff {
    AppImageCompare compare; ///< the image diff (NULL: PNGs too are compared by their bytes)
    AppFigureImage image;    ///< PDFs and SVGs as PNGs on the page (NULL: shown as links)
    void *context;
    int threshold, shift;   ///< the compare's options, for the report
    long max_pixels;        ///< same
    const char *report_dir; ///< index.html, report.json and the images shown; NULL: none
    int update;             ///< 1: then make the baseline the fresh figures
} AppFolderDiff;

/// Compares the figures of two folders and prints one line per figure that is not identical and
/// a summary line. Returns the exit status: 0 every figure matches (or --update refreshed the
/// baseline), 1 a figure is changed, missing or extra, 2 bad input (a folder that is not one, an
/// unreadable figure, a report or update that could not be written; message on stderr).
int app_diff_folders(const char *baseline, const char *fresh, const AppFolderDiff *options);

#endif
