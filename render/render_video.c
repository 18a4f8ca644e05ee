/* SPDX-License-Identifier: MIT */
/* render_video.c: MP4 movies through libavformat, libavcodec and libswscale.
 *
 * Each frame is drawn by the chosen drawer (OSMesa or Cairo) in the caller's thread straight into
 * a slot of a small queue (OSMesa: grain layer by GL, annotations by render_cairo_overlay); an
 * encoder thread takes the slots in order, converts them to yuv420p (BT.709 matrix, limited
 * range) and runs the encoder and the muxer, so drawing (and simulating) the next frame overlaps
 * with the conversion and x264, which runs its own threads as well. Output goes to path.tmp,
 * renamed at close.
 *
 * Errors are sticky: the first one is kept, later render_movie_frame calls do nothing and
 * render_movie_close returns it. Colour handling: the drawers give full-range sRGB; the stream is
 * BT.709 limited range and tagged so (anchors-render 2c: sws defaults to BT.601, which a decoder
 * honouring a BT.709 tag shows off by up to 12 levels). */
#include "render/internal.h"
#include "sim/sim.h"

#include <errno.h>
#include <libavcodec/avcodec.h>
#include <libavformat/avformat.h>
#include <libavutil/dict.h>
#include <libavutil/error.h>
#include <libavutil/frame.h>
#include <libavutil/log.h>
#include <libswscale/swscale.h>
#include <math.h>
#include <pthread.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* Drawn frames waiting for the encoder: enough to absorb jitter between drawing and x264, few
 * enough to bound memory (8 MiB drawn + 3 MiB converted each at 1080p). */
enum { QUEUE_SLOTS = 3 };

/* Default libx264 preset: the fastest one that gives H.264 High profile (ultrafast turns off
 * CABAC, B-frames and the 8x8 transform: Constrained Baseline). bench/README.md ("Movie size")
 * compares it with ultrafast at the same PSNR and SSIM (bench_render_movie_size);
 * RenderMovieDef.preset picks another. */
#define DEFAULT_PRESET RENDER_MOVIE_PRESET

/* One queue entry: the drawn image (drawer's format) and its yuv420p conversion. */
typedef struct Slot {
    RenderImage image; ///< OSMesa: allocated once; Cairo: the drawer's image, freed on reuse
    AVFrame *frame;
} Slot;

struct RenderMovie {
    RenderStyle style;
    int range_fixed; /* render_color_lock has fixed the style's colour range */
    RenderDrawer drawer;
    int width, height; ///< pixels
    int threads;       ///< the drawing's (RenderMovieDef)
    int quiet;
    long frames_expected;
    char *path, *temp_path;
    int temp_created; ///< 1 once path.tmp exists (removed on failure)
    RenderGl *gl;
    RenderHelper *helper; ///< Cairo frames: draws the lower half (render_cairo_draw_split), or NULL
    AVFormatContext *format;
    AVCodecContext *codec;
    AVStream *stream;
    AVPacket *packet;       ///< encoder thread only
    struct SwsContext *sws; ///< encoder thread only
    int overlay;            ///< 1: OSMesa frames get render_cairo_overlay
    Slot slots[QUEUE_SLOTS];
    long next_pts;
    /* queue: slots head .. head + filled - 1 (mod QUEUE_SLOTS) wait for the encoder thread */
    pthread_mutex_t lock;
    pthread_cond_t changed;
    int sync_ready;
    int head, filled, stopping;
    int thread_running;
    pthread_t thread;
    /* sticky error, under lock */
    int failed;
    char message[512];
    /* progress */
    double start_s, last_report_s; ///< monotonic seconds
    long frames_given, frames_encoded;
    double encode_s; ///< encoder thread's busy time (convert + encode), under lock
    int progress_shown;
};

/* Keeps the first error only (either thread). */
__attribute__((format(printf, 2, 3))) static void fail(RenderMovie *movie, const char *format, ...)
{
    if (movie->sync_ready)
        pthread_mutex_lock(&movie->lock);
    if (!movie->failed) {
        movie->failed = 1;
        va_list args;
        va_start(args, format);
        vsnprintf(movie->message, sizeof movie->message, format, args);
        va_end(args);
    }
    if (movie->sync_ready) {
        pthread_cond_broadcast(&movie->changed);
        pthread_mutex_unlock(&movie->lock);
    }
}

static int has_failed(RenderMovie *movie)
{
    pthread_mutex_lock(&movie->lock);
    int failed = movie->failed;
    pthread_mutex_unlock(&movie->lock);
    return failed;
}

static const char *av_message(int code, char *buffer, size_t size)
{
    if (av_strerror(code, buffer, size) < 0)
        snprintf(buffer, size, "libav error %d", code);
    return buffer;
}

/* Sends one frame (NULL = flush) and writes every packet the encoder has ready. 0 on success. */
static int encode(RenderMovie *movie, const AVFrame *frame)
{
    char text[128];
    int rc = avcodec_send_frame(movie->codec, frame);
    if (rc < 0) {
        fail(movie, "%s: encoder refused a frame: %s", movie->path,
             av_message(rc, text, sizeof text));
        return -1;
    }
    for (;;) {
        rc = avcodec_receive_packet(movie->codec, movie->packet);
        if (rc == AVERROR(EAGAIN) || rc == AVERROR_EOF)
            return 0; /* needs more input / fully flushed */
        if (rc < 0) {
            fail(movie, "%s: encoding failed: %s", movie->path, av_message(rc, text, sizeof text));
            return -1;
        }
        av_packet_rescale_ts(movie->packet, movie->codec->time_base, movie->stream->time_base);
        movie->packet->stream_index = movie->stream->index;
        rc = av_interleaved_write_frame(movie->format, movie->packet); /* takes the packet */
        if (rc < 0) {
            fail(movie, "%s: writing failed: %s", movie->path, av_message(rc, text, sizeof text));
            return -1;
        }
    }
}

/* Pixel layout of a drawer's image for swscale. */
static enum AVPixelFormat source_format(RenderPixelFormat format)
{
    /* Cairo ARGB32 is B,G,R,A bytes on little-endian; frames are opaque, so premultiplication
     * does not matter. */
    return format == RENDER_PIXEL_RGBA ? AV_PIX_FMT_RGBA : AV_PIX_FMT_BGRA;
}

/* Converts a drawn image into its slot's yuv420p frame (encoder thread). */
static int convert(RenderMovie *movie, const RenderImage *image, AVFrame *slot)
{
    char text[128];
    if (image->width != movie->width || image->height != movie->height) {
        fail(movie, "%s: drawer gave %dx%d for a %dx%d movie", movie->path, image->width,
             image->height, movie->width, movie->height);
        return -1;
    }
    struct SwsContext *sws = sws_getCachedContext(
        movie->sws, movie->width, movie->height, source_format(image->format), movie->width,
        movie->height, AV_PIX_FMT_YUV420P, SWS_BILINEAR | SWS_ACCURATE_RND, NULL, NULL, NULL);
    if (!sws) {
        fail(movie, "%s: cannot set up the colour conversion", movie->path);
        return -1;
    }
    if (sws != movie->sws) {
        movie->sws = sws;
        /* Source full-range RGB, destination BT.709 limited range (16-235 luma). */
        const int *bt709 = sws_getCoefficients(SWS_CS_ITU709);
        if (sws_setColorspaceDetails(sws, bt709, 1, bt709, 0, 0, 1 << 16, 1 << 16) < 0) {
            fail(movie, "%s: swscale cannot convert to BT.709", movie->path);
            return -1;
        }
    }
    int rc = av_frame_make_writable(slot); /* copies if the encoder still holds the buffer */
    if (rc < 0) {
        fail(movie, "%s: %s", movie->path, av_message(rc, text, sizeof text));
        return -1;
    }
    const uint8_t *const planes[1] = {image->pixels};
    const int strides[1] = {image->stride};
    sws_scale(sws, planes, strides, 0, movie->height, slot->data, slot->linesize);
    return 0;
}

static void *encoder_main(void *argument)
{
    RenderMovie *movie = argument;
    pthread_mutex_lock(&movie->lock);
    for (;;) {
        while (movie->filled == 0 && !movie->stopping)
            pthread_cond_wait(&movie->changed, &movie->lock);
        if (movie->filled == 0)
            break;
        Slot *slot = &movie->slots[movie->head];
        int skip = movie->failed; /* after an error, drain the queue without encoding */
        pthread_mutex_unlock(&movie->lock);
        double t0 = sim_clock_seconds(SIM_CLOCK_WALL);
        if (!skip && convert(movie, &slot->image, slot->frame) == 0)
            encode(movie, slot->frame);
        double busy = sim_clock_seconds(SIM_CLOCK_WALL) - t0;
        pthread_mutex_lock(&movie->lock);
        movie->encode_s += busy;
        movie->head = (movie->head + 1) % QUEUE_SLOTS;
        movie->filled -= 1;
        movie->frames_encoded += 1;
        pthread_cond_broadcast(&movie->changed);
    }
    pthread_mutex_unlock(&movie->lock);
    return NULL;
}

static void movie_free(RenderMovie *movie)
{
    if (!movie)
        return;
    if (movie->thread_running) {
        pthread_mutex_lock(&movie->lock);
        movie->stopping = 1;
        pthread_cond_broadcast(&movie->changed);
        pthread_mutex_unlock(&movie->lock);
        pthread_join(movie->thread, NULL);
        movie->thread_running = 0;
    }
    if (movie->format && movie->format->pb)
        avio_closep(&movie->format->pb);
    if (movie->temp_created)
        remove(movie->temp_path);
    avformat_free_context(movie->format);
    avcodec_free_context(&movie->codec);
    av_packet_free(&movie->packet);
    sws_freeContext(movie->sws);
    for (int k = 0; k < QUEUE_SLOTS; ++k) {
        av_frame_free(&movie->slots[k].frame);
        render_image_free(&movie->slots[k].image);
    }
    render_gl_destroy(movie->gl);
    render_helper_destroy(movie->helper);
    if (movie->sync_ready) {
        pthread_cond_destroy(&movie->changed);
        pthread_mutex_destroy(&movie->lock);
    }
    free(movie->path);
    free(movie->temp_path);
    free(movie);
}

static char *copy_string(const char *text, const char *suffix)
{
    size_t a = strlen(text), b = strlen(suffix);
    char *copy = malloc(a + b + 1);
    if (copy) {
        memcpy(copy, text, a);
        memcpy(copy + a, suffix, b + 1);
    }
    return copy;
}

/* The BT.709 tags go on the codec context (x264 writes them into the VUI, the MP4 muxer into a
 * colr box) and on every frame. */
static void tag_bt709(enum AVColorSpace *space, enum AVColorPrimaries *primaries,
                      enum AVColorTransferCharacteristic *transfer, enum AVColorRange *range)
{
    *space = AVCOL_SPC_BT709;
    *primaries = AVCOL_PRI_BT709;
    *transfer = AVCOL_TRC_BT709;
    *range = AVCOL_RANGE_MPEG;
}

/* Checks a movie's definition; gives its frame rate and CRF with the defaults applied. 0, or -1
 * with a message in err. */
static int check_movie_def(const RenderMovieDef *def, const RenderStyle *style, double *fps,
                           int *crf, char *err, size_t err_size)
{
    if (!def || !style || !def->path || !def->path[0]) {
        snprintf(err, err_size, "movie: no definition, style or path");
        return -1;
    }
    if (style->width <= 0 || style->height <= 0 || style->width % 2 || style->height % 2) {
        snprintf(err, err_size,
                 "%s: movie size %dx%d: width and height must be positive and even (H.264 "
                 "yuv420p)",
                 def->path, style->width, style->height);
        return -1;
    }
    *fps = def->fps == 0.0 ? 30.0 : def->fps;
    if (!(*fps > 0.0 && *fps <= RENDER_VIDEO_MAX_FPS)) {
        snprintf(err, err_size, "%s: frame rate %g outside (0, %g] frames/s", def->path, *fps,
                 RENDER_VIDEO_MAX_FPS);
        return -1;
    }
    *crf = def->crf == 0 ? 20 : def->crf;
    if (*crf < 0 || *crf > 51) {
        snprintf(err, err_size, "%s: quality (CRF) %d outside 0..51", def->path, *crf);
        return -1;
    }
    if (def->drawer != RENDER_DRAWER_CAIRO && def->drawer != RENDER_DRAWER_OSMESA) {
        snprintf(err, err_size, "%s: unknown drawer %d", def->path, (int)def->drawer);
        return -1;
    }
    return 0;
}

/* A movie with its lock, its settings and its paths, nothing of libav yet; NULL with a message
 * in err. */
static RenderMovie *movie_create(const RenderMovieDef *def, const RenderStyle *style, char *err,
                                 size_t err_size)
{
    RenderMovie *movie = calloc(1, sizeof *movie);
    if (!movie) {
        snprintf(err, err_size, "%s: out of memory", def->path);
        return NULL;
    }
    if (pthread_mutex_init(&movie->lock, NULL) != 0) {
        free(movie);
        snprintf(err, err_size, "%s: cannot create a lock", def->path);
        return NULL;
    }
    if (pthread_cond_init(&movie->changed, NULL) != 0) {
        pthread_mutex_destroy(&movie->lock);
        free(movie);
        snprintf(err, err_size, "%s: cannot create a condition variable", def->path);
        return NULL;
    }
    movie->sync_ready = 1;
    movie->style = *style;
    movie->drawer = def->drawer;
    movie->threads = def->threads;
    movie->width = style->width;
    movie->height = style->height;
    movie->quiet = def->quiet;
    movie->frames_expected = def->frames_expected;
    movie->path = copy_string(def->path, "");
    movie->temp_path = copy_string(def->path, ".tmp");
    if (!movie->path || !movie->temp_path) {
        snprintf(err, err_size, "%s: out of memory", def->path);
        movie_free(movie);
        return NULL;
    }
    return movie;
}

/* The encoder: libx264 unless told otherwise; without it, mpeg4 (always built in). NULL after
 * fail(). */
static const AVCodec *find_encoder(RenderMovie *movie, const RenderMovieDef *def)
{
    const char *name = def->encoder ? def->encoder : "libx264";
    const AVCodec *encoder = avcodec_find_encoder_by_name(name);
    if (!encoder && !def->encoder) {
        encoder = avcodec_find_encoder(AV_CODEC_ID_MPEG4);
        if (encoder)
            fprintf(
                stderr,
                "warning: %s: libavcodec has no libx264 encoder; encoding MPEG-4 part 2 instead "
                "(larger files; a libavcodec built with libx264 gives H.264 High profile)\n",
                movie->path);
    }
    if (!encoder)
        fail(movie, "%s: libavcodec has no encoder named %s", movie->path, name);
    return encoder;
}

/* The MP4 muxer, its stream, the encoder's context and a packet. 0, or -1 after fail(). */
static int alloc_muxer(RenderMovie *movie, const AVCodec *encoder)
{
    char text[128];
    /* The muxer is named: the .tmp name does not tell the format. */
    int rc = avformat_alloc_output_context2(&movie->format, NULL, "mp4", movie->temp_path);
    if (rc < 0 || !movie->format) {
        fail(movie, "%s: cannot set up the MP4 muxer: %s", movie->path,
             av_message(rc, text, sizeof text));
        return -1;
    }
    movie->stream = avformat_new_stream(movie->format, NULL);
    movie->codec = avcodec_alloc_context3(encoder);
    movie->packet = av_packet_alloc();
    if (!movie->stream || !movie->codec || !movie->packet) {
        fail(movie, "%s: out of memory", movie->path);
        return -1;
    }
    return 0;
}

/* Sets the encoder's picture, rate and quality (x264: preset and CRF in *options; others: a
 * fixed quantiser). */
static void configure_encoder(RenderMovie *movie, const RenderMovieDef *def, const AVCodec *encoder,
                              AVRational rate, double fps, int crf, AVDictionary **options)
{
    AVCodecContext *codec = movie->codec;
    codec->width = movie->width;
    codec->height = movie->height;
    codec->pix_fmt = AV_PIX_FMT_YUV420P;
    codec->framerate = rate;
    codec->time_base = av_inv_q(rate);
    codec->gop_size = (int)ceil(2.0 * fps); /* a key frame every 2 s keeps movies seekable */
    codec->sample_aspect_ratio = (AVRational){1, 1};
    /* A fixed thread count: x264's output depends on it (deterministic for a given count), so
     * the same scene gives the same bytes on any machine; its own choice follows the cores. */
    codec->thread_count = RENDER_MOVIE_THREADS;
    tag_bt709(&codec->colorspace, &codec->color_primaries, &codec->color_trc, &codec->color_range);
    if (movie->format->oformat->flags & AVFMT_GLOBALHEADER)
        codec->flags |= AV_CODEC_FLAG_GLOBAL_HEADER; /* MP4 keeps SPS/PPS in avcC */
    if (strcmp(encoder->name, "libx264") == 0) {
        char value[16];
        snprintf(value, sizeof value, "%d", crf);
        av_dict_set(options, "preset", def->preset ? def->preset : DEFAULT_PRESET, 0);
        av_dict_set(options, "crf", value, 0);
    } else {
        /* No CRF outside x264: a fixed quantiser of similar visual quality (CRF 20 -> q 4). */
        int q = (int)lround(crf / 5.0);
        codec->flags |= AV_CODEC_FLAG_QSCALE;
        codec->global_quality = FF_QP2LAMBDA * (q < 2 ? 2 : q > 31 ? 31 : q);
        if (def->preset)
            fprintf(stderr, "warning: %s: preset %s ignored by encoder %s\n", movie->path,
                    def->preset, encoder->name);
    }
}

/* Configures and opens the encoder, copies its parameters to the stream and tags the file with
 * the scene. 0, or -1 after fail(). */
static int open_encoder(RenderMovie *movie, const RenderMovieDef *def, const AVCodec *encoder,
                        double fps, int crf)
{
    char text[128];
    AVDictionary *options = NULL;
    AVRational rate = av_d2q(fps, 100000); /* 30 -> 30/1, 29.97 -> 2997/100 */
    configure_encoder(movie, def, encoder, rate, fps, crf, &options);
    AVCodecContext *codec = movie->codec;
    int rc = avcodec_open2(codec, encoder, &options);
    if (rc < 0) {
        fail(movie, "%s: cannot open encoder %s: %s", movie->path, encoder->name,
             av_message(rc, text, sizeof text));
        av_dict_free(&options);
        return -1;
    }
    if (av_dict_count(options) > 0) {
        fail(movie, "%s: encoder %s does not know option %s=%s", movie->path, encoder->name,
             av_dict_get(options, "", NULL, AV_DICT_IGNORE_SUFFIX)->key,
             av_dict_get(options, "", NULL, AV_DICT_IGNORE_SUFFIX)->value);
        av_dict_free(&options);
        return -1;
    }
    av_dict_free(&options);
    rc = avcodec_parameters_from_context(movie->stream->codecpar, codec);
    if (rc < 0) {
        fail(movie, "%s: out of memory", movie->path);
        return -1;
    }
    movie->stream->time_base = codec->time_base; /* a hint: the muxer may change it */
    movie->stream->avg_frame_rate = rate;
    if (def->meta.scene) {
        snprintf(text, sizeof text, "sablier scene %s, seed %llu", def->meta.scene,
                 (unsigned long long)def->meta.seed);
        av_dict_set(&movie->format->metadata, "title", def->meta.scene, 0);
        av_dict_set(&movie->format->metadata, "comment", text, 0);
    }
    return 0;
}

/* Creates PATH.tmp and writes the MP4 header. 0, or -1 after fail(). */
static int open_file(RenderMovie *movie)
{
    char text[128];
    /* PATH.tmp made anew as a regular file, PATH refused unless one (sim_open_output) */
    const char *why = NULL;
    FILE *fresh = sim_open_output(movie->path, &why);
    if (!fresh) {
        fail(movie, "%s: %s", movie->path, why);
        return -1;
    }
    fclose(fresh);
    int rc = avio_open(&movie->format->pb, movie->temp_path, AVIO_FLAG_WRITE);
    if (rc < 0) {
        fail(movie, "%s: cannot create %s: %s", movie->path, movie->temp_path,
             av_message(rc, text, sizeof text));
        return -1;
    }
    movie->temp_created = 1;
    AVDictionary *options = NULL;
    av_dict_set(&options, "movflags", "+faststart", 0); /* moov before mdat: web playback */
    rc = avformat_write_header(movie->format, &options);
    av_dict_free(&options);
    if (rc < 0) {
        fail(movie, "%s: cannot write the MP4 header: %s", movie->path,
             av_message(rc, text, sizeof text));
        return -1;
    }
    return 0;
}

/* The queue's yuv420p frames and, for OSMesa, its drawn images and the GL context. 0, or -1
 * after fail(). */
static int alloc_slots(RenderMovie *movie, const RenderStyle *style)
{
    for (int k = 0; k < QUEUE_SLOTS; ++k) {
        AVFrame *slot = av_frame_alloc();
        movie->slots[k].frame = slot;
        if (!slot) {
            fail(movie, "%s: out of memory", movie->path);
            return -1;
        }
        slot->format = AV_PIX_FMT_YUV420P;
        slot->width = movie->width;
        slot->height = movie->height;
        tag_bt709(&slot->colorspace, &slot->color_primaries, &slot->color_trc, &slot->color_range);
        if (av_frame_get_buffer(slot, 0) < 0) {
            fail(movie, "%s: out of memory", movie->path);
            return -1;
        }
    }
    if (movie->drawer != RENDER_DRAWER_OSMESA) {
        /* Cairo: the lower half of each frame in a helper thread (none given: one band) */
        if (render_band_count(movie->height, movie->threads) == 2)
            movie->helper = render_helper_create();
        return 0;
    }
    /* GL draws the grain layer; Cairo adds the annotations on the same pixels. */
    movie->overlay = style->colorbar || style->time_stamp || style->scale_bar || style->title ||
                     style->velocity_arrows || style->velocity_field || style->arch_ids;
    for (int k = 0; k < QUEUE_SLOTS; ++k) {
        if (render_image_alloc(&movie->slots[k].image, movie->width, movie->height,
                               RENDER_PIXEL_BGRA_PREMUL) != 0) {
            fail(movie, "%s: out of memory", movie->path);
            return -1;
        }
    }
    char message[256];
    movie->gl = render_gl_create(movie->width, movie->height, message, sizeof message);
    if (!movie->gl) {
        fail(movie, "%s: %s", movie->path, message);
        return -1;
    }
    return 0;
}

RenderMovie *render_movie_open(const RenderMovieDef *def, const RenderStyle *style, char *err,
                               size_t err_size)
{
    double fps;
    int crf;
    if (check_movie_def(def, style, &fps, &crf, err, err_size) != 0)
        return NULL;
    /* libav's default level prints x264's statistics and the muxer's faststart notice on every
     * movie; keep warnings and errors unless the program chose a level itself. */
    if (av_log_get_level() == AV_LOG_INFO)
        av_log_set_level(AV_LOG_WARNING);
    RenderMovie *movie = movie_create(def, style, err, err_size);
    if (!movie)
        return NULL;
    const AVCodec *encoder = find_encoder(movie, def);
    if (!encoder || alloc_muxer(movie, encoder) != 0 ||
        open_encoder(movie, def, encoder, fps, crf) != 0 || open_file(movie) != 0 ||
        alloc_slots(movie, style) != 0)
        goto fail;
    if (pthread_create(&movie->thread, NULL, encoder_main, movie) != 0) {
        fail(movie, "%s: cannot start the encoder thread", movie->path);
        goto fail;
    }
    movie->thread_running = 1;
    movie->start_s = sim_clock_seconds(SIM_CLOCK_WALL);
    movie->last_report_s = movie->start_s;
    return movie;

fail:
    snprintf(err, err_size, "%s", movie->message);
    movie_free(movie);
    return NULL;
}

double render_movie_encode_left(RenderMovie *movie, long frames_to_come)
{
    if (!movie)
        return 0.0;
    pthread_mutex_lock(&movie->lock);
    long encoded = movie->frames_encoded, queued = movie->frames_given - encoded;
    double busy = movie->encode_s;
    pthread_mutex_unlock(&movie->lock);
    if (encoded <= 0)
        return 0.0;
    /* x264 holds about a second of frames (lookahead, B-frames) until the flush at close */
    double held = fmin((double)movie->frames_given, av_q2d(av_inv_q(movie->codec->time_base)));
    double frames = (double)queued + (double)(frames_to_come > 0 ? frames_to_come : 0) + held;
    return frames * busy / (double)encoded;
}

static void report_progress(RenderMovie *movie, int final)
{
    double now = sim_clock_seconds(SIM_CLOCK_WALL);
    double elapsed = now - movie->start_s;
    /* Short encodes stay silent; long ones update one line about once a second. */
    if (movie->quiet || (!final && (elapsed < 2.0 || now - movie->last_report_s < 1.0)))
        return;
    if (final && !movie->progress_shown)
        return;
    movie->last_report_s = now;
    movie->progress_shown = 1;
    double rate = elapsed > 0.0 ? (double)movie->frames_given / elapsed : 0.0;
    long to_come = movie->frames_expected - movie->frames_given;
    if (to_come > 0 && rate > 0.0) /* drawing or encoding, whichever finishes last */
        fprintf(stderr, "\rmovie %s: frame %ld/%ld, %.1f frames/s, ETA %.0f s   ", movie->path,
                movie->frames_given, movie->frames_expected, rate,
                fmax((double)to_come / rate, render_movie_encode_left(movie, to_come)));
    else
        fprintf(stderr, "\rmovie %s: frame %ld, %.1f frames/s   ", movie->path, movie->frames_given,
                rate);
    if (final)
        fputc('\n', stderr);
}

int render_movie_frame(RenderMovie *movie, const SimFrame *frame)
{
    if (!movie)
        return -1;
    if (has_failed(movie))
        return -1; /* sticky: the first error is returned by render_movie_close */
    if (!frame) {
        fail(movie, "%s: no frame", movie->path);
        return -1;
    }
    /* Wait for a free slot; the slot after the queued ones is the caller's to fill. */
    pthread_mutex_lock(&movie->lock);
    while (movie->filled == QUEUE_SLOTS && !movie->failed)
        pthread_cond_wait(&movie->changed, &movie->lock);
    int failed = movie->failed;
    Slot *slot = &movie->slots[(movie->head + movie->filled) % QUEUE_SLOTS];
    pthread_mutex_unlock(&movie->lock);
    if (failed)
        return -1;
    char message[256];
    if (!movie->range_fixed) /* one colour range for the whole movie */
        movie->range_fixed = render_color_lock(frame, &movie->style);
    if (movie->drawer == RENDER_DRAWER_OSMESA) {
        if (render_gl_frame_to(movie->gl, frame, &movie->style, &slot->image, message,
                               sizeof message)) {
            fail(movie, "%s: frame %ld: %s", movie->path, movie->frames_given, message);
            return -1;
        }
        if (movie->overlay && render_cairo_overlay(frame, &movie->style, &slot->image) != 0) {
            fail(movie, "%s: frame %ld: Cairo overlay failed", movie->path, movie->frames_given);
            return -1;
        }
    } else {
        render_image_free(&slot->image);
        if (render_cairo_draw_split(frame, &movie->style, &slot->image, movie->helper) != 0) {
            fail(movie, "%s: frame %ld: Cairo drawing failed", movie->path, movie->frames_given);
            return -1;
        }
    }
    slot->frame->pts = movie->next_pts++;
    pthread_mutex_lock(&movie->lock);
    movie->filled += 1;
    pthread_cond_broadcast(&movie->changed);
    pthread_mutex_unlock(&movie->lock);
    movie->frames_given += 1;
    report_progress(movie, 0);
    return 0;
}

int render_movie_close(RenderMovie *movie, char *err, size_t err_size)
{
    char text[128];
    if (!movie) {
        snprintf(err, err_size, "movie: not open");
        return -1;
    }
    /* Let the encoder thread empty the queue, then flush in this thread. */
    pthread_mutex_lock(&movie->lock);
    movie->stopping = 1;
    pthread_cond_broadcast(&movie->changed);
    pthread_mutex_unlock(&movie->lock);
    if (movie->thread_running) {
        pthread_join(movie->thread, NULL);
        movie->thread_running = 0;
    }
    report_progress(movie, 1);
    if (!movie->failed && movie->frames_given == 0)
        fail(movie, "%s: no frames", movie->path);
    if (!movie->failed)
        encode(movie, NULL); /* x264 holds about a second of frames (lookahead, B-frames) */
    if (!movie->failed) {
        int rc = av_write_trailer(movie->format); /* faststart: rewrites with moov first */
        if (rc < 0)
            fail(movie, "%s: cannot finish the MP4: %s", movie->path,
                 av_message(rc, text, sizeof text));
    }
    if (movie->format->pb) {
        int rc = avio_closep(&movie->format->pb);
        if (rc < 0)
            fail(movie, "%s: cannot close %s: %s", movie->path, movie->temp_path,
                 av_message(rc, text, sizeof text));
    }
    if (!movie->failed) {
        if (rename(movie->temp_path, movie->path) != 0)
            fail(movie, "%s: cannot rename %s: %s", movie->path, movie->temp_path, strerror(errno));
        else
            movie->temp_created = 0;
    }
    int failed = movie->failed;
    if (!failed && !movie->quiet) {
        double elapsed = sim_clock_seconds(SIM_CLOCK_WALL) - movie->start_s;
        fprintf(stderr, "movie %s: %ld frames (%.1f s of video) in %.1f s, %s\n", movie->path,
                movie->frames_given, (double)movie->frames_given * av_q2d(movie->codec->time_base),
                elapsed, movie->codec->codec->name);
    }
    if (failed)
        snprintf(err, err_size, "%s", movie->message);
    else if (err_size > 0)
        err[0] = '\0';
    movie_free(movie);
    return failed ? -1 : 0;
}

static int movie_consume(void *context, const SimFrame *frame)
{
    return render_movie_frame(context, frame) != 0;
}

SimFrameSink render_movie_sink(RenderMovie *movie)
{
    return (SimFrameSink){.consume = movie_consume, .context = movie};
}
