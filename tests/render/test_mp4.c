/* SPDX-License-Identifier: MIT */
/* test_mp4.c: MP4 movies read back with libavformat/libavcodec: codec, frame count, duration,
 * size, yuv420p, BT.709 tags and colours, faststart, odd sizes, path.tmp then rename, sticky
 * errors, the mpeg4 encoder, both drawers, the drawing's threads. Outputs under out/render-tests/.
 */
#define _GNU_SOURCE /* pin.h: sched_setaffinity */
#include "fixture.h"
#include "pin.h"
#include "test.h"

#include "render/internal.h"

#include <dirent.h>
#include <libavcodec/avcodec.h>
#include <libavformat/avformat.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <sys/stat.h>

#define OUT_DIR "out/render-tests"

static void make_out_dir(void)
{
    mkdir("out", 0755);
    mkdir(OUT_DIR, 0755);
}

static int file_exists(const char *path)
{
    struct stat st;
    return stat(path, &st) == 0;
}

/* A small frame: three disks in a row, one of them fixed, touching pairs with contacts. */
typedef struct Scene {
    double x[3], y[3], r[3], angle[3], vx[3], vy[3], omega[3], force[3];
    int species[3];
    unsigned flags[3];
    uint32_t id[3];
    SimContact contacts[2];
    SimFrame frame;
} Scene;

static void scene_init(Scene *s, double shift)
{
    memset(s, 0, sizeof *s);
    for (int i = 0; i < 3; ++i) {
        s->x[i] = 0.3 + 0.2 * i + shift;
        s->y[i] = 0.5;
        s->r[i] = 0.1;
        s->force[i] = 1.0 + i;
        s->species[i] = i;
        s->id[i] = (uint32_t)i;
    }
    s->flags[2] = SIM_GRAIN_FIXED;
    s->contacts[0] = (SimContact){.i = 0, .j = 1, .normal_force = 1.0, .x = 0.4, .y = 0.5};
    s->contacts[1] = (SimContact){.i = 1, .j = 2, .normal_force = 2.0, .x = 0.6, .y = 0.5};
    s->frame = (SimFrame){.count = 3,
                          .mobile_count = 2,
                          .x = s->x,
                          .y = s->y,
                          .angle = s->angle,
                          .radius = s->r,
                          .vx = s->vx,
                          .vy = s->vy,
                          .omega = s->omega,
                          .species = s->species,
                          .flags = s->flags,
                          .id = s->id,
                          .force = s->force,
                          .contact_count = 2,
                          .contacts = s->contacts};
}

/* A style showing the grain layer only, over a fixed world window [0, 1] x [0, 0.75]. */
static RenderStyle small_style(int width, int height)
{
    RenderStyle style = render_style_default();
    style.width = width;
    style.height = height;
    style.view_x0 = 0.0;
    style.view_y0 = 0.0;
    style.view_x1 = 1.0;
    style.view_y1 = 0.75;
    style.colorbar = 0;
    style.time_stamp = 0;
    style.scale_bar = 0;
    style.title = NULL;
    return style;
}

static RenderMovieDef movie_def(const char *path, RenderDrawer drawer)
{
    RenderMovieDef def = {0};
    def.path = path;
    def.drawer = drawer;
    def.fps = 25.0;
    def.crf = 18;
    def.quiet = 1;
    def.meta.scene = "test";
    def.meta.seed = 7;
    return def;
}

/* What a movie file holds, read back through libavformat and libavcodec. */
typedef struct Probe {
    enum AVCodecID codec;
    int width, height;
    int pix_fmt;
    enum AVColorSpace space;
    enum AVColorPrimaries primaries;
    enum AVColorTransferCharacteristic transfer;
    enum AVColorRange range;
    double duration;           ///< s, from the stream
    double fps;                ///< average frame rate
    int frames;                ///< decoded
    int sample_count;          ///< frames sampled into sample_yuv
    uint8_t sample_yuv[64][3]; ///< Y, U, V at the image centre of decoded frames 0..63
    int strip_x0;              ///< > 0: strip_change measured over the columns x >= strip_x0
    double strip_change;       ///< largest mean |Y - Y of frame 0| over the strip, luma levels
    uint8_t *strip;            ///< frame 0's luma over the strip (probe_movie's own)
} Probe;

/* Mean |Y - Y of frame 0| over the columns x >= strip_x0 (frame 0's luma kept on the first call).
 */
static void probe_strip(Probe *probe, const AVFrame *frame)
{
    int x0 = probe->strip_x0, w = frame->width - x0, h = frame->height;
    if (x0 <= 0 || w <= 0)
        return;
    if (!probe->strip) {
        probe->strip = malloc((size_t)w * (size_t)h);
        for (int y = 0; probe->strip && y < h; ++y)
            memcpy(probe->strip + (size_t)y * w, frame->data[0] + y * frame->linesize[0] + x0,
                   (size_t)w);
        return;
    }
    double sum = 0;
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x)
            sum += abs(frame->data[0][y * frame->linesize[0] + x0 + x] -
                       probe->strip[(size_t)y * w + x]);
    probe->strip_change = fmax(probe->strip_change, sum / ((double)w * h));
}

/* probe_movie, measuring strip_change over the columns x >= strip_x0 (0: none). */
static int probe_movie_strip(const char *path, int strip_x0, Probe *probe)
{
    memset(probe, 0, sizeof *probe);
    probe->strip_x0 = strip_x0;
    AVFormatContext *format = NULL;
    AVCodecContext *codec = NULL;
    AVPacket *packet = av_packet_alloc();
    AVFrame *frame = av_frame_alloc();
    int ok = 0;
    if (!packet || !frame || avformat_open_input(&format, path, NULL, NULL) < 0)
        goto done;
    if (avformat_find_stream_info(format, NULL) < 0)
        goto done;
    int index = av_find_best_stream(format, AVMEDIA_TYPE_VIDEO, -1, -1, NULL, 0);
    if (index < 0)
        goto done;
    AVStream *stream = format->streams[index];
    AVCodecParameters *par = stream->codecpar;
    probe->codec = par->codec_id;
    probe->width = par->width;
    probe->height = par->height;
    probe->pix_fmt = par->format;
    probe->space = par->color_space;
    probe->primaries = par->color_primaries;
    probe->transfer = par->color_trc;
    probe->range = par->color_range;
    probe->duration = stream->duration > 0 ? (double)stream->duration * av_q2d(stream->time_base)
                                           : (double)format->duration / AV_TIME_BASE;
    probe->fps = av_q2d(stream->avg_frame_rate);
    const AVCodec *decoder = avcodec_find_decoder(par->codec_id);
    codec = decoder ? avcodec_alloc_context3(decoder) : NULL;
    if (!codec || avcodec_parameters_to_context(codec, par) < 0 ||
        avcodec_open2(codec, decoder, NULL) < 0)
        goto done;
    int draining = 0;
    for (;;) {
        if (!draining) {
            int rc = av_read_frame(format, packet);
            if (rc < 0) {
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
            if (probe->sample_count < 64 && frame->format == AV_PIX_FMT_YUV420P) {
                int cx = frame->width / 2, cy = frame->height / 2;
                uint8_t *yuv = probe->sample_yuv[probe->sample_count++];
                yuv[0] = frame->data[0][cy * frame->linesize[0] + cx];
                yuv[1] = frame->data[1][(cy / 2) * frame->linesize[1] + cx / 2];
                yuv[2] = frame->data[2][(cy / 2) * frame->linesize[2] + cx / 2];
            }
            if (frame->format == AV_PIX_FMT_YUV420P)
                probe_strip(probe, frame);
            probe->frames += 1;
            av_frame_unref(frame);
        }
        if (rc == AVERROR_EOF || (draining && rc != AVERROR(EAGAIN)))
            break;
    }
    ok = 1;
done:
    free(probe->strip);
    probe->strip = NULL;
    avcodec_free_context(&codec);
    avformat_close_input(&format);
    av_packet_free(&packet);
    av_frame_free(&frame);
    return ok ? 0 : -1;
}

/* Top-level MP4 boxes in file order: 1 when "moov" comes before "mdat" (+faststart). */
static int probe_movie(const char *path, Probe *probe)
{
    return probe_movie_strip(path, 0, probe);
}

static int moov_before_mdat(const char *path)
{
    FILE *file = fopen(path, "rb");
    if (!file)
        return 0;
    int moov = -1, mdat = -1, k = 0;
    unsigned char head[16];
    while (fread(head, 1, 8, file) == 8) {
        uint64_t size =
            (uint64_t)head[0] << 24 | (uint64_t)head[1] << 16 | (uint64_t)head[2] << 8 | head[3];
        long skip = 8;
        if (size == 1) {
            if (fread(head + 8, 1, 8, file) != 8)
                break;
            size = 0;
            for (int b = 8; b < 16; ++b)
                size = size << 8 | head[b];
            skip = 16;
        }
        if (!memcmp(head + 4, "moov", 4))
            moov = k;
        if (!memcmp(head + 4, "mdat", 4))
            mdat = k;
        if (size < (uint64_t)skip || fseek(file, (long)size - skip, SEEK_CUR) != 0)
            break;
        ++k;
    }
    fclose(file);
    return moov >= 0 && mdat >= 0 && moov < mdat;
}

/* Writes `count` frames of the little scene moving right. */
static int write_movie(const RenderMovieDef *def, const RenderStyle *style, int count)
{
    char err[512];
    RenderMovie *movie = render_movie_open(def, style, err, sizeof err);
    if (!movie) {
        fprintf(stderr, "open: %s\n", err);
        return -1;
    }
    Scene scene;
    for (int k = 0; k < count; ++k) {
        scene_init(&scene, 0.005 * k);
        if (render_movie_frame(movie, &scene.frame) != 0)
            break;
    }
    if (render_movie_close(movie, err, sizeof err) != 0) {
        fprintf(stderr, "close: %s\n", err);
        return -1;
    }
    return 0;
}

static int mp4_properties(void)
{
    make_out_dir();
    const char *path = OUT_DIR "/mp4_properties.mp4";
    RenderStyle style = small_style(320, 240);
    RenderMovieDef def = movie_def(path, RENDER_DRAWER_OSMESA);
    TEST_ASSERT(write_movie(&def, &style, 40) == 0);
    Probe p;
    TEST_ASSERT(probe_movie(path, &p) == 0);
    TEST_ASSERT(p.codec == AV_CODEC_ID_H264);
    TEST_ASSERT(p.width == 320 && p.height == 240);
    TEST_ASSERT(p.pix_fmt == AV_PIX_FMT_YUV420P);
    TEST_ASSERT(p.space == AVCOL_SPC_BT709);
    TEST_ASSERT(p.primaries == AVCOL_PRI_BT709);
    TEST_ASSERT(p.transfer == AVCOL_TRC_BT709);
    TEST_ASSERT(p.range == AVCOL_RANGE_MPEG);
    TEST_ASSERT(p.frames == 40); /* the encoder was flushed: no tail lost */
    TEST_NEAR(p.duration, 40 / 25.0, 1e-3);
    TEST_NEAR(p.fps, 25.0, 1e-6);
    TEST_ASSERT(moov_before_mdat(path));
    return 0;
}

/* Limited-range BT.709 of 8-bit sRGB values (ITU-R BT.709-6 table 3, 8-bit quantisation). */
static void bt709_of(uint32_t rgb, double yuv[3])
{
    double r = (rgb >> 16 & 255) / 255.0, g = (rgb >> 8 & 255) / 255.0, b = (rgb & 255) / 255.0;
    double y = 0.2126 * r + 0.7152 * g + 0.0722 * b;
    yuv[0] = 16.0 + 219.0 * y;
    yuv[1] = 128.0 + 224.0 * (b - y) / 1.8556;
    yuv[2] = 128.0 + 224.0 * (r - y) / 1.5748;
}

/* Back to 8-bit RGB, as a player honouring the BT.709 tag does. */
static void rgb_of_bt709(const uint8_t yuv[3], double rgb[3])
{
    double y = (yuv[0] - 16.0) / 219.0, u = (yuv[1] - 128.0) / 224.0, v = (yuv[2] - 128.0) / 224.0;
    double r = y + 1.5748 * v;
    double b = y + 1.8556 * u;
    double g = (y - 0.2126 * r - 0.0722 * b) / 0.7152;
    rgb[0] = 255.0 * r;
    rgb[1] = 255.0 * g;
    rgb[2] = 255.0 * b;
}

/* Frames filled with known colours decode back within a few levels: the conversion is BT.709
 * (BT.601 would miss viridis yellow's U/V by 5-6 levels and teal's by 12 after decoding). */
static int mp4_colour_roundtrip(void)
{
    make_out_dir();
    static const uint32_t colours[] = {0xfde725, 0x21918c, 0xd62728, 0x440154, 0x808080};

    enum { COLOURS = 5, PER = 6 };

    /* One movie per colour: the background is part of the movie's style. */
    for (int drawer = 0; drawer < 2; ++drawer) {
        for (int c = 0; c < COLOURS; ++c) {
            char path[128];
            snprintf(path, sizeof path, OUT_DIR "/mp4_colour_%s_%06x.mp4",
                     drawer ? "cairo" : "osmesa", (unsigned)colours[c]);
            RenderStyle style = small_style(128, 96);
            style.background_rgb = colours[c];
            RenderMovieDef def =
                movie_def(path, drawer ? RENDER_DRAWER_CAIRO : RENDER_DRAWER_OSMESA);
            char err[512];
            RenderMovie *movie = render_movie_open(&def, &style, err, sizeof err);
            TEST_ASSERT(movie != NULL);
            SimFrame empty = {0};
            for (int k = 0; k < PER; ++k)
                TEST_ASSERT(render_movie_frame(movie, &empty) == 0);
            TEST_ASSERT(render_movie_close(movie, err, sizeof err) == 0);
            Probe p;
            TEST_ASSERT(probe_movie(path, &p) == 0);
            TEST_ASSERT(p.frames == PER && p.sample_count == PER);
            double want[3], got[3];
            bt709_of(colours[c], want);
            for (int k = 0; k < PER; ++k) {
                for (int q = 0; q < 3; ++q)
                    TEST_NEAR(p.sample_yuv[k][q], want[q], 1.5);
                rgb_of_bt709(p.sample_yuv[k], got);
                TEST_NEAR(got[0], (double)(colours[c] >> 16 & 255), 4.0);
                TEST_NEAR(got[1], (double)(colours[c] >> 8 & 255), 4.0);
                TEST_NEAR(got[2], (double)(colours[c] & 255), 4.0);
            }
        }
    }
    return 0;
}

static int mp4_odd_size_rejected(void)
{
    make_out_dir();
    const char *path = OUT_DIR "/mp4_odd.mp4";
    remove(path);
    char err[512] = "";
    RenderMovieDef def = movie_def(path, RENDER_DRAWER_OSMESA);
    RenderStyle style = small_style(321, 240);
    TEST_ASSERT(render_movie_open(&def, &style, err, sizeof err) == NULL);
    TEST_ASSERT(strstr(err, "321x240") != NULL && strstr(err, "even") != NULL);
    style = small_style(320, 239);
    TEST_ASSERT(render_movie_open(&def, &style, err, sizeof err) == NULL);
    TEST_ASSERT(strstr(err, "320x239") != NULL);
    TEST_ASSERT(!file_exists(path));
    TEST_ASSERT(!file_exists(OUT_DIR "/mp4_odd.mp4.tmp"));
    return 0;
}

static int mp4_bad_settings_rejected(void)
{
    char err[512] = "";
    RenderStyle style = small_style(64, 64);
    RenderMovieDef def = movie_def(OUT_DIR "/mp4_bad.mp4", RENDER_DRAWER_OSMESA);
    def.fps = -1.0;
    TEST_ASSERT(render_movie_open(&def, &style, err, sizeof err) == NULL);
    TEST_ASSERT(strstr(err, "frame rate") != NULL);
    def = movie_def(OUT_DIR "/mp4_bad.mp4", RENDER_DRAWER_OSMESA);
    def.crf = 60;
    TEST_ASSERT(render_movie_open(&def, &style, err, sizeof err) == NULL);
    TEST_ASSERT(strstr(err, "CRF") != NULL);
    def = movie_def(OUT_DIR "/mp4_bad.mp4", RENDER_DRAWER_OSMESA);
    def.encoder = "no-such-encoder";
    TEST_ASSERT(render_movie_open(&def, &style, err, sizeof err) == NULL);
    TEST_ASSERT(strstr(err, "no-such-encoder") != NULL);
    def = movie_def(OUT_DIR "/mp4_bad.mp4", RENDER_DRAWER_OSMESA);
    def.preset = "warp-speed";
    TEST_ASSERT(render_movie_open(&def, &style, err, sizeof err) == NULL);
    TEST_ASSERT(!file_exists(OUT_DIR "/mp4_bad.mp4.tmp"));
    TEST_ASSERT(render_movie_close(NULL, err, sizeof err) != 0);
    return 0;
}

/* The movie is written to path.tmp; the final name appears only at close. */
static int mp4_temp_then_rename(void)
{
    make_out_dir();
    const char *path = OUT_DIR "/mp4_rename.mp4";
    const char *temp = OUT_DIR "/mp4_rename.mp4.tmp";
    remove(path);
    RenderStyle style = small_style(160, 120);
    RenderMovieDef def = movie_def(path, RENDER_DRAWER_OSMESA);
    char err[512];
    RenderMovie *movie = render_movie_open(&def, &style, err, sizeof err);
    TEST_ASSERT(movie != NULL);
    Scene scene;
    scene_init(&scene, 0.0);
    SimFrameSink sink = render_movie_sink(movie);
    for (int k = 0; k < 10; ++k)
        TEST_ASSERT(sink.consume(sink.context, &scene.frame) == 0);
    TEST_ASSERT(file_exists(temp));
    TEST_ASSERT(!file_exists(path));
    TEST_ASSERT(render_movie_close(movie, err, sizeof err) == 0);
    TEST_ASSERT(file_exists(path));
    TEST_ASSERT(!file_exists(temp));
    Probe p;
    TEST_ASSERT(probe_movie(path, &p) == 0 && p.frames == 10);
    return 0;
}

/* The first error is kept; later frames do nothing; close returns it and leaves no file. */
static int mp4_errors_sticky(void)
{
    make_out_dir();
    const char *path = OUT_DIR "/mp4_sticky.mp4";
    remove(path);
    RenderStyle style = small_style(160, 120);
    RenderMovieDef def = movie_def(path, RENDER_DRAWER_OSMESA);
    char err[512];
    RenderMovie *movie = render_movie_open(&def, &style, err, sizeof err);
    TEST_ASSERT(movie != NULL);
    Scene scene;
    scene_init(&scene, 0.0);
    TEST_ASSERT(render_movie_frame(movie, &scene.frame) == 0);
    TEST_ASSERT(render_movie_frame(movie, NULL) != 0);
    TEST_ASSERT(render_movie_frame(movie, &scene.frame) != 0);
    TEST_ASSERT(render_movie_close(movie, err, sizeof err) != 0);
    TEST_ASSERT(strstr(err, "no frame") != NULL);
    TEST_ASSERT(!file_exists(path));
    TEST_ASSERT(!file_exists(OUT_DIR "/mp4_sticky.mp4.tmp"));
    /* A movie without frames is an error too, and leaves nothing behind. */
    movie = render_movie_open(&def, &style, err, sizeof err);
    TEST_ASSERT(movie != NULL);
    TEST_ASSERT(render_movie_close(movie, err, sizeof err) != 0);
    TEST_ASSERT(strstr(err, "no frames") != NULL);
    TEST_ASSERT(!file_exists(path));
    return 0;
}

/* The H.264 profile_idc of a movie: byte 1 of its avcC box (ISO/IEC 14496-15 5.2.4.1: version,
 * AVCProfileIndication, ...), which libavformat gives as the stream's extradata. -1 if none. */
static int avc_profile(const char *path)
{
    AVFormatContext *format = NULL;
    int profile = -1;
    if (avformat_open_input(&format, path, NULL, NULL) < 0)
        return -1;
    if (avformat_find_stream_info(format, NULL) >= 0 && format->nb_streams == 1) {
        const AVCodecParameters *par = format->streams[0]->codecpar;
        if (par->extradata_size >= 4 && par->extradata[0] == 1)
            profile = par->extradata[1];
    }
    avformat_close_input(&format);
    return profile;
}

static long file_size(const char *path)
{
    struct stat st;
    return stat(path, &st) == 0 ? (long)st.st_size : -1;
}

/* The default settings give H.264 High profile (profile_idc 100), with both drawers. */
static int mp4_high_profile(void)
{
    make_out_dir();
    for (int drawer = 0; drawer < 2; ++drawer) {
        const char *path = drawer ? OUT_DIR "/mp4_high_cairo.mp4" : OUT_DIR "/mp4_high.mp4";
        RenderStyle style = small_style(320, 240);
        RenderMovieDef def = movie_def(path, drawer ? RENDER_DRAWER_CAIRO : RENDER_DRAWER_OSMESA);
        def.crf = 0; /* the default quality */
        TEST_ASSERT(write_movie(&def, &style, 30) == 0);
        TEST_ASSERT(avc_profile(path) == 100);
        TEST_ASSERT(moov_before_mdat(path));
    }
    return 0;
}

/* A higher CRF gives a smaller file: 14, 20, 26, 32 strictly decreasing. */
static int mp4_crf_size(void)
{
    make_out_dir();
    static const int crfs[] = {14, 20, 26, 32};
    long previous = -1;
    for (int k = 0; k < 4; ++k) {
        char path[128];
        snprintf(path, sizeof path, OUT_DIR "/mp4_crf_%d.mp4", crfs[k]);
        RenderStyle style = small_style(320, 240);
        style.force_chains = 1;
        RenderMovieDef def = movie_def(path, RENDER_DRAWER_CAIRO);
        def.crf = crfs[k];
        TEST_ASSERT(write_movie(&def, &style, 30) == 0);
        long size = file_size(path);
        TEST_ASSERT(size > 0);
        if (previous > 0)
            TEST_ASSERT(size < previous);
        previous = size;
    }
    return 0;
}

/* The same frames give the same bytes, and the encoder runs RENDER_MOVIE_THREADS threads
 * whatever the machine's cores (x264 writes its settings in the stream: "threads=N"), so the
 * bytes do not depend on the machine either. */
/* 1 when the two files hold the same bytes (and at least one); their contents in *first. */
static int same_files(const char *a, const char *b, char **first)
{
    long size = file_size(a);
    *first = NULL;
    if (size <= 0 || size != file_size(b))
        return 0;
    char *bytes[2] = {malloc((size_t)size + 1), malloc((size_t)size + 1)};
    int same = bytes[0] && bytes[1] && fixture_read(a, bytes[0], size) == size &&
               fixture_read(b, bytes[1], size) == size &&
               memcmp(bytes[0], bytes[1], (size_t)size) == 0;
    if (bytes[0])
        bytes[0][size] = '\0';
    free(bytes[1]);
    *first = bytes[0];
    return same;
}

static int mp4_same_bytes(void)
{
    make_out_dir();
    const char *paths[2] = {OUT_DIR "/mp4_same_a.mp4", OUT_DIR "/mp4_same_b.mp4"};
    for (int k = 0; k < 2; ++k) {
        RenderStyle style = small_style(320, 240);
        RenderMovieDef def = movie_def(paths[k], RENDER_DRAWER_CAIRO);
        TEST_ASSERT(write_movie(&def, &style, 40) == 0);
    }
    char *bytes = NULL;
    TEST_ASSERT(same_files(paths[0], paths[1], &bytes));
    const long size = file_size(paths[0]);
    char want[32];
    snprintf(want, sizeof want, " threads=%d ", RENDER_MOVIE_THREADS);
    const char *sei = NULL;
    for (long i = 0; i + 8 < size && !sei; ++i) /* x264's SEI text, inside mdat */
        if (memcmp(bytes + i, "options:", 8) == 0)
            sei = bytes + i;
    TEST_ASSERT(sei != NULL && strstr(sei, want) != NULL);
    free(bytes);
    return 0;
}

/* A Cairo movie drawn in two bands on two threads (render_cairo_draw_split, SABLIER_BANDS=2) has
 * the bytes of one drawn in one band (SABLIER_BANDS=1): the frames' pixels are the same. The
 * frames carry force chains, velocity arrows, a colour bar, a time stamp and a scale bar. */
static int mp4_cairo_bands_same_bytes(void)
{
    make_out_dir();
    const char *paths[2] = {OUT_DIR "/mp4_bands_1.mp4", OUT_DIR "/mp4_bands_2.mp4"};
    for (int k = 0; k < 2; ++k) {
        RenderStyle style = small_style(320, 242); /* an odd half: bands of 121 rows */
        style.force_chains = 1;
        style.velocity_arrows = 1;
        style.colorbar = 1;
        style.time_stamp = 1;
        style.scale_bar = 1;
        RenderMovieDef def = movie_def(paths[k], RENDER_DRAWER_CAIRO);
        setenv("SABLIER_BANDS", k ? "2" : "1", 1);
        const int rc = write_movie(&def, &style, 12);
        unsetenv("SABLIER_BANDS");
        TEST_ASSERT(rc == 0);
    }
    char *bytes = NULL;
    TEST_ASSERT(same_files(paths[0], paths[1], &bytes));
    free(bytes);
    return 0;
}

/* The threads of this process (/proc/self/task), -1 when they cannot be read. */
static int task_count(void)
{
    DIR *d = opendir("/proc/self/task");
    if (!d)
        return -1;
    int n = 0;
    for (struct dirent *e; (e = readdir(d));)
        n += e->d_name[0] != '.';
    closedir(d);
    return n;
}

static int bands_of_1080_rows(void)
{
    return render_band_count(1080, 0);
}

/* The frames' drawing stays within the movie's threads (RenderMovieDef.threads, `sablier run
 * --threads N`) and the CPUs of the affinity mask: one band on one thread, two from two threads
 * on, the CPUs when 0; too few rows for two bands, one; SABLIER_BANDS still chooses. */
static int band_count_within_threads(void)
{
    unsetenv("SABLIER_BANDS");
    TEST_ASSERT(render_band_count(1080, 1) == 1);
    TEST_ASSERT(render_band_count(1080, 2) == 2 && render_band_count(1080, 16) == 2);
    TEST_ASSERT(render_band_count(100, 16) == 1);
    TEST_ASSERT(render_band_count(1080, 0) == (sim_cpu_count() >= 2 ? 2 : 1));
    TEST_ASSERT(test_on_one_cpu(bands_of_1080_rows) == 1);
    setenv("SABLIER_BANDS", "2", 1);
    const int forced = render_band_count(1080, 1);
    unsetenv("SABLIER_BANDS");
    TEST_ASSERT(forced == 2);
    return 0;
}

/* The threads a movie of `drawer` opened with `threads` starts (its frames drawn and encoded). */
static int movie_tasks(RenderDrawer drawer, int threads)
{
    RenderStyle style = small_style(320, 242);
    RenderMovieDef def = movie_def(OUT_DIR "/mp4_threads.mp4", drawer);
    def.threads = threads;
    char err[512];
    const int before = task_count();
    RenderMovie *movie = render_movie_open(&def, &style, err, sizeof err);
    if (!movie || before < 0)
        return -1;
    const int started = task_count() - before;
    Scene scene;
    scene_init(&scene, 0.0);
    const int drawn = render_movie_frame(movie, &scene.frame);
    if (render_movie_close(movie, err, sizeof err) != 0 || drawn != 0)
        return -1;
    return started;
}

/* A Cairo movie opened with `threads` = 1 draws on the calling thread alone: it starts one thread
 * fewer than the same movie with 2 (the lower band's helper); the encoder's threads are the same.
 * The OSMesa drawer's bands follow the CPUs alone (its bands agree with one band up to rounding,
 * and the bytes must not depend on --threads): the same threads with 1 and 2. */
static int mp4_threads_bound_drawing(void)
{
    make_out_dir();
    unsetenv("SABLIER_BANDS");
    const int one = movie_tasks(RENDER_DRAWER_CAIRO, 1), two = movie_tasks(RENDER_DRAWER_CAIRO, 2);
    fprintf(stderr, "threads a Cairo movie starts: %d drawing on one thread, %d on two\n", one,
            two);
    TEST_ASSERT(one > 0 && two == one + 1);
    TEST_ASSERT(movie_tasks(RENDER_DRAWER_OSMESA, 1) > 0); /* llvmpipe's threads, kept after */
    const int gl_one = movie_tasks(RENDER_DRAWER_OSMESA, 1),
              gl_two = movie_tasks(RENDER_DRAWER_OSMESA, 2);
    fprintf(stderr, "threads an OSMesa movie starts: %d with --threads 1, %d with 2\n", gl_one,
            gl_two);
    TEST_ASSERT(gl_one > 0 && gl_one == gl_two);
    return 0;
}

/* The encoder used when libx264 is absent still gives a playable, tagged MP4. */
static int mp4_mpeg4_encoder(void)
{
    make_out_dir();
    const char *path = OUT_DIR "/mp4_mpeg4.mp4";
    RenderStyle style = small_style(160, 120);
    RenderMovieDef def = movie_def(path, RENDER_DRAWER_OSMESA);
    def.encoder = "mpeg4";
    def.fps = 30.0;
    TEST_ASSERT(write_movie(&def, &style, 12) == 0);
    Probe p;
    TEST_ASSERT(probe_movie(path, &p) == 0);
    TEST_ASSERT(p.codec == AV_CODEC_ID_MPEG4);
    TEST_ASSERT(p.frames == 12);
    TEST_ASSERT(p.pix_fmt == AV_PIX_FMT_YUV420P);
    TEST_NEAR(p.duration, 12 / 30.0, 1e-3);
    return 0;
}

/* The Cairo drawer feeds the same writer. */
static int mp4_cairo_drawer(void)
{
    make_out_dir();
    const char *path = OUT_DIR "/mp4_cairo.mp4";
    RenderStyle style = small_style(320, 240);
    style.force_chains = 1;
    RenderMovieDef def = movie_def(path, RENDER_DRAWER_CAIRO);
    def.fps = 24.0;
    TEST_ASSERT(write_movie(&def, &style, 20) == 0);
    Probe p;
    TEST_ASSERT(probe_movie(path, &p) == 0);
    TEST_ASSERT(p.codec == AV_CODEC_ID_H264 && p.frames == 20);
    TEST_ASSERT(p.width == 320 && p.height == 240 && p.space == AVCOL_SPC_BT709);
    TEST_NEAR(p.duration, 20 / 24.0, 1e-3);
    return 0;
}

/* One colour scale per movie: frames whose forces grow twentyfold keep the colour bar of the
 * first (range fixed there with headroom, render_color_lock), with the saturation triangle, in
 * both drawers: the decoded bar and its labels do not change (only the codec's noise). */
static int colorbar_strip_change(RenderDrawer drawer, const char *path, double *change)
{
    RenderStyle style = small_style(320, 240);
    style.color_by = RENDER_COLOR_FORCE;
    style.colorbar = 1;
    style.font_size = 12;
    char err[512];
    RenderMovieDef def = movie_def(path, drawer);
    RenderMovie *movie = render_movie_open(&def, &style, err, sizeof err);
    TEST_ASSERT(movie != NULL);
    Scene scene;
    for (int k = 0; k < 12; ++k) {
        scene_init(&scene, 0.0);
        for (int i = 0; i < 3; ++i)
            scene.force[i] *= 1.0 + 2.0 * k;
        TEST_ASSERT(render_movie_frame(movie, &scene.frame) == 0);
    }
    TEST_ASSERT(render_movie_close(movie, err, sizeof err) == 0);
    RenderView view;
    scene_init(&scene, 0.0);
    render_view_fit(&scene.frame, &style, &view);
    Probe p;
    TEST_ASSERT(probe_movie_strip(path, (int)ceil(view.plot_x + view.plot_w) + 2, &p) == 0);
    TEST_ASSERT(p.frames == 12);
    *change = p.strip_change;
    return 0;
}

static int mp4_one_colour_scale(void)
{
    make_out_dir();
    double cairo = -1, gl = -1;
    TEST_ASSERT(
        colorbar_strip_change(RENDER_DRAWER_CAIRO, OUT_DIR "/mp4_scale_cairo.mp4", &cairo) == 0);
    fprintf(stderr, "colour bar change over the movie, Cairo: %.3f luma levels\n", cairo);
    TEST_ASSERT(cairo >= 0 && cairo < 1.0);
    TEST_ASSERT(colorbar_strip_change(RENDER_DRAWER_OSMESA, OUT_DIR "/mp4_scale_gl.mp4", &gl) == 0);
    fprintf(stderr, "colour bar change over the movie, OSMesa: %.3f luma levels\n", gl);
    TEST_ASSERT(gl >= 0 && gl < 1.0);
    return 0;
}

TEST_MAIN(TEST_CASE(mp4_properties), TEST_CASE(mp4_colour_roundtrip),
          TEST_CASE(mp4_odd_size_rejected), TEST_CASE(mp4_bad_settings_rejected),
          TEST_CASE(mp4_temp_then_rename), TEST_CASE(mp4_errors_sticky),
          TEST_CASE(mp4_mpeg4_encoder), TEST_CASE(mp4_cairo_drawer), TEST_CASE(mp4_high_profile),
          TEST_CASE(mp4_crf_size), TEST_CASE(mp4_same_bytes), TEST_CASE(mp4_one_colour_scale),
          TEST_CASE(mp4_cairo_bands_same_bytes), TEST_CASE(band_count_within_threads),
          TEST_CASE(mp4_threads_bound_drawing))
