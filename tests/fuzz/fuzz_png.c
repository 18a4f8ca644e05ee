/* SPDX-License-Identifier: MIT */
/* fuzz_png: render_png_read (the reader behind `sablier diff`) on any bytes: an image or an error,
 * never a crash, a leak or a decompression bomb. */
#include "fuzz_input.h"

#include "render/render.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    const char *path = fuzz_input_file(data, size, ".png");
    if (!path)
        return 0;
    RenderImage image;
    char err[512];
    if (render_png_read(path, &image, err, sizeof err) == 0)
        render_image_free(&image);
    unlink(path);
    return 0;
}
