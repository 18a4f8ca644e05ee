/* SPDX-License-Identifier: MIT */
/* bench_render_movie_size.c: movie size of the previous encoder settings (libx264 ultrafast:
 * Constrained Baseline) against the current ones (RENDER_MOVIE_PRESET: High profile) at the same
 * quality, on the frames of a real movie.
 *
 *     bench_render_movie_size SOURCE.mp4 [old_crf [max_frames [tune [preset [x264-params]]]]]
 *
 * (defaults 20, 300, no tune, RENDER_MOVIE_PRESET, none: the current settings; the last three
 * try others for the current side)
 *
 * SOURCE is a lossless movie of sablier's own pipeline (output.crf = 0: the yuv420p frames the
 * encoder was given, exactly), e.g. the quick crater collapse:
 *     sablier run scenes/crater/quick.scene --out /tmp/q --set output.crf=0 \
 *         --set output.movie_speed=0.25 --set 'output.movie=["collapse"]'
 * Its frames are encoded with the previous settings at old_crf, then with the current settings
 * at CRF old_crf - 8 .. old_crf + 4; each result is decoded and compared with the source frames
 * by PSNR (all three planes, one MSE over every sample) and SSIM (luma, 8x8 windows on a 4-pixel
 * grid with the constants of Wang et al. 2004, IEEE Trans. Image Process. 13(4) 600, eq. 13).
 * "Same quality" is the largest CRF whose PSNR and SSIM are both at least the previous
 * settings'; the bench prints the sizes and their ratio, and the CPU time of each encode. */
#include "render/render.h"

#include <libavcodec/avcodec.h>
#include <libavformat/avformat.h>
#include <libavutil/opt.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

typedef struct Frames {
    int width, height, count;
    uint8_t **yuv; ///< count frames, planes packed: Y (w*h), U, V (w/2*h/2 each)
} Frames;

static size_t frame_bytes(const Frames *f)
{
    return (size_t)f->width * (size_t)f->height * 3 / 2;
}

/* Packs a decoded yuv420p frame. */
static uint8_t *pack(const AVFrame *frame, int width, int height)
{
    uint8_t *out = malloc((size_t)width * (size_t)height * 3 / 2);
    if (!out)
        return NULL;
    uint8_t *p = out;
    for (int plane = 0; plane < 3; ++plane) {
        int w = plane ? width / 2 : width, h = plane ? height / 2 : height;
        for (int row = 0; row < h; ++row, p += w)
            memcpy(p, frame->data[plane] + (size_t)row * (size_t)frame->linesize[plane], (size_t)w);
    }
    return out;
}

/* Decodes every frame of a movie held in `path` (at most `max` kept). 0, or -1. */
static int decode(const char *path, int max, Frames *out)
{
    memset(out, 0, sizeof *out);
    AVFormatContext *format = NULL;
    AVCodecContext *codec = NULL;
    AVPacket *packet = av_packet_alloc();
    AVFrame *frame = av_frame_alloc();
    int ok = -1;
    if (!packet || !frame || avformat_open_input(&format, path, NULL, NULL) < 0 ||
        avformat_find_stream_info(format, NULL) < 0)
        goto done;
    int index = av_find_best_stream(format, AVMEDIA_TYPE_VIDEO, -1, -1, NULL, 0);
    if (index < 0)
        goto done;
    const AVCodecParameters *par = format->streams[index]->codecpar;
    const AVCodec *decoder = avcodec_find_decoder(par->codec_id);
    codec = decoder ? avcodec_alloc_context3(decoder) : NULL;
    if (!codec || avcodec_parameters_to_context(codec, par) < 0 ||
        avcodec_open2(codec, decoder, NULL) < 0)
        goto done;
    out->width = par->width;
    out->height = par->height;
    out->yuv = calloc((size_t)max, sizeof *out->yuv);
    if (!out->yuv)
        goto done;
    int draining = 0;
    for (;;) {
        if (!draining) {
            if (av_read_frame(format, packet) < 0) {
                draining = 1;
                avcodec_send_packet(codec, NULL);
            } else {
                if (packet->stream_index == index)
                    avcodec_send_packet(codec, packet);
                av_packet_unref(packet);
            }
        }
        int rc;
        while ((rc = avcodec_receive_frame(codec, frame)) == 0) {
            if (frame->format != AV_PIX_FMT_YUV420P)
                goto done;
            if (out->count < max &&
                !(out->yuv[out->count++] = pack(frame, out->width, out->height)))
                goto done;
            av_frame_unref(frame);
        }
        if (rc == AVERROR_EOF || (draining && rc != AVERROR(EAGAIN)))
            break;
    }
    ok = 0;
done:
    avcodec_free_context(&codec);
    avformat_close_input(&format);
    av_packet_free(&packet);
    av_frame_free(&frame);
    return ok;
}

static void frames_free(Frames *f)
{
    for (int k = 0; k < f->count; ++k)
        free(f->yuv[k]);
    free(f->yuv);
    memset(f, 0, sizeof *f);
}

/* Encodes the frames with libx264 (preset, CRF, the movies' thread count) into an MP4 at `path`,
 * as render_video.c does. The file's size in bytes, or -1. */
static const char *tune;   /* x264 tune of the current settings (argument 4), NULL = none */
static const char *params; /* x264-params of the current settings (argument 6), NULL = none */

static long encode(const Frames *src, const char *preset, int current, int crf, const char *path)
{
    const AVCodec *encoder = avcodec_find_encoder_by_name("libx264");
    AVFormatContext *format = NULL;
    AVCodecContext *codec = encoder ? avcodec_alloc_context3(encoder) : NULL;
    AVPacket *packet = av_packet_alloc();
    AVFrame *frame = av_frame_alloc();
    long size = -1;
    if (!codec || !packet || !frame ||
        avformat_alloc_output_context2(&format, NULL, "mp4", path) < 0)
        goto done;
    AVStream *stream = avformat_new_stream(format, NULL);
    codec->width = src->width;
    codec->height = src->height;
    codec->pix_fmt = AV_PIX_FMT_YUV420P;
    codec->time_base = (AVRational){1, 25};
    codec->framerate = (AVRational){25, 1};
    codec->gop_size = 50;
    codec->thread_count = RENDER_MOVIE_THREADS;
    codec->flags |= AV_CODEC_FLAG_GLOBAL_HEADER;
    char value[16];
    snprintf(value, sizeof value, "%d", crf);
    av_opt_set(codec->priv_data, "preset", preset, 0);
    av_opt_set(codec->priv_data, "crf", value, 0);
    if (tune && current)
        av_opt_set(codec->priv_data, "tune", tune, 0);
    if (params && current)
        av_opt_set(codec->priv_data, "x264-params", params, 0);
    if (!stream || avcodec_open2(codec, encoder, NULL) < 0 ||
        avcodec_parameters_from_context(stream->codecpar, codec) < 0)
        goto done;
    stream->time_base = codec->time_base;
    stream->avg_frame_rate = codec->framerate;
    if (avio_open(&format->pb, path, AVIO_FLAG_WRITE) < 0 ||
        avformat_write_header(format, NULL) < 0)
        goto done;
    frame->format = AV_PIX_FMT_YUV420P;
    frame->width = src->width;
    frame->height = src->height;
    if (av_frame_get_buffer(frame, 0) < 0)
        goto done;
    for (int k = 0; k <= src->count; ++k) {
        if (k < src->count) {
            if (av_frame_make_writable(frame) < 0)
                goto done;
            const uint8_t *p = src->yuv[k];
            for (int plane = 0; plane < 3; ++plane) {
                int w = plane ? src->width / 2 : src->width;
                int h = plane ? src->height / 2 : src->height;
                for (int row = 0; row < h; ++row, p += w)
                    memcpy(frame->data[plane] + (size_t)row * (size_t)frame->linesize[plane], p,
                           (size_t)w);
            }
            frame->pts = k;
        }
        if (avcodec_send_frame(codec, k < src->count ? frame : NULL) < 0)
            goto done;
        while (avcodec_receive_packet(codec, packet) == 0) {
            av_packet_rescale_ts(packet, codec->time_base, stream->time_base);
            packet->stream_index = stream->index;
            if (av_interleaved_write_frame(format, packet) < 0)
                goto done;
        }
    }
    if (av_write_trailer(format) < 0 || avio_closep(&format->pb) < 0)
        goto done;
    struct stat st;
    size = stat(path, &st) == 0 ? (long)st.st_size : -1;
done:
    if (format && format->pb)
        avio_closep(&format->pb);
    avformat_free_context(format);
    avcodec_free_context(&codec);
    av_packet_free(&packet);
    av_frame_free(&frame);
    return size;
}

/* SSIM of two 8-bit planes: mean over 8x8 windows on a 4-pixel grid (Wang et al. 2004, eq. 13,
 * C1 = (0.01 L)^2, C2 = (0.03 L)^2, L = 255). */
static double ssim_plane(const uint8_t *a, const uint8_t *b, int width, int height)
{
    const double c1 = 6.5025, c2 = 58.5225;
    double sum = 0.0;
    long windows = 0;
    for (int y = 0; y + 8 <= height; y += 4)
        for (int x = 0; x + 8 <= width; x += 4) {
            double sa = 0, sb = 0, saa = 0, sbb = 0, sab = 0;
            for (int j = 0; j < 8; ++j)
                for (int i = 0; i < 8; ++i) {
                    double p = a[(y + j) * width + x + i], q = b[(y + j) * width + x + i];
                    sa += p;
                    sb += q;
                    saa += p * p;
                    sbb += q * q;
                    sab += p * q;
                }
            double ma = sa / 64, mb = sb / 64;
            double va = saa / 64 - ma * ma, vb = sbb / 64 - mb * mb, cov = sab / 64 - ma * mb;
            sum +=
                (2 * ma * mb + c1) * (2 * cov + c2) / ((ma * ma + mb * mb + c1) * (va + vb + c2));
            windows += 1;
        }
    return windows ? sum / (double)windows : 1.0;
}

/* PSNR (dB, all samples of all frames) and mean luma SSIM of `got` against `ref`. */
static void quality(const Frames *ref, const Frames *got, double *psnr, double *ssim)
{
    double se = 0.0, s = 0.0;
    size_t n = frame_bytes(ref);
    for (int k = 0; k < ref->count; ++k) {
        for (size_t i = 0; i < n; ++i) {
            double d = (double)ref->yuv[k][i] - (double)got->yuv[k][i];
            se += d * d;
        }
        s += ssim_plane(ref->yuv[k], got->yuv[k], ref->width, ref->height);
    }
    double mse = se / ((double)n * (double)ref->count);
    *psnr = mse > 0.0 ? 10.0 * log10(255.0 * 255.0 / mse) : (double)INFINITY;
    *ssim = s / (double)ref->count;
}

typedef struct Result {
    long bytes;
    double psnr, ssim, cpu_ms; ///< dB, 1, CPU ms per frame (encode only)
} Result;

static int measure(const Frames *src, const char *preset, int current, int crf, Result *r)
{
    char path[128];
    snprintf(path, sizeof path, "/tmp/bench_render_movie_size_%ld.mp4", (long)getpid());
    double t0 = sim_clock_seconds(SIM_CLOCK_PROCESS);
    r->bytes = encode(src, preset, current, crf, path);
    r->cpu_ms = 1e3 * (sim_clock_seconds(SIM_CLOCK_PROCESS) - t0) / src->count;
    Frames got;
    int rc = r->bytes < 0 ? -1 : decode(path, src->count + 5, &got);
    if (rc != 0 || got.count != src->count) {
        fprintf(stderr, "encoding with %s at CRF %d failed\n", preset, crf);
        return -1;
    }
    quality(src, &got, &r->psnr, &r->ssim);
    frames_free(&got);
    remove(path);
    printf("%-10s CRF %2d  %9ld bytes  PSNR %6.3f dB  SSIM %.5f  %6.1f CPU ms/frame\n", preset, crf,
           r->bytes, r->psnr, r->ssim, r->cpu_ms);
    return 0;
}

int main(int argc, char **argv)
{
    if (argc < 2) {
        fprintf(stderr, "usage: bench_render_movie_size SOURCE.mp4 [old_crf [max_frames]]\n");
        return 2;
    }
    int old_crf = argc > 2 ? atoi(argv[2]) : 20, max = argc > 3 ? atoi(argv[3]) : 300;
    tune = argc > 4 && argv[4][0] ? argv[4] : NULL;
    const char *preset = argc > 5 ? argv[5] : RENDER_MOVIE_PRESET;
    params = argc > 6 ? argv[6] : NULL;
    av_log_set_level(AV_LOG_WARNING);
    Frames src;
    if (max < 1 || decode(argv[1], max, &src) != 0 || src.count == 0) {
        fprintf(stderr, "%s: cannot read the frames\n", argv[1]);
        return 1;
    }
    printf("%s: %d frames of %dx%d, encoder threads %d\n", argv[1], src.count, src.width,
           src.height, RENDER_MOVIE_THREADS);
    Result old, now, best = {0};
    int best_crf = -1;
    if (measure(&src, "ultrafast", 0, old_crf, &old) != 0)
        return 1;
    for (int crf = old_crf - 8; crf <= old_crf + 4; ++crf) {
        if (measure(&src, preset, 1, crf, &now) != 0)
            return 1;
        if (now.psnr >= old.psnr && now.ssim >= old.ssim) {
            best = now;
            best_crf = crf;
        }
    }
    if (best_crf < 0)
        printf("no CRF of %s reaches the quality of ultrafast CRF %d\n", preset, old_crf);
    else
        printf("same quality: %s CRF %d is %.3f x the bytes of ultrafast CRF %d (%ld / %ld)\n",
               preset, best_crf, (double)best.bytes / (double)old.bytes, old_crf, best.bytes,
               old.bytes);
    frames_free(&src);
    return 0;
}
