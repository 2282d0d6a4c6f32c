/* Benchmark of hair file input and output (issue 14, item 8): the Sintel TressFX groom
 * of ../shared/hair-data converted to .hair (aim: under 50 ms), and reading and writing
 * a .hair file of 1 million strands of 32 points against plain stdio moving the same
 * bytes (aim: within twice its time). */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "bench.h"
#include "core/core_internal.h"
#include "hairkit/hair_formats.h"

/* The best of `reps` runs of a step (seconds), or -1 when it failed. */
typedef int (*Step)(void *user);
static double best_of(int reps, Step step, void *user)
{
    double best = 1e30;
    for (int r = 0; r < reps; r++) {
        const double t0 = hk_seconds_now();
        if (!step(user)) return -1.0;
        best = fmin(best, hk_seconds_now() - t0);
    }
    return best;
}

typedef struct Io {
    const char *in, *out; /* paths */
    hk_HairFile hair;     /* the groom written, or read back */
    unsigned char *bytes; /* the plain copy's buffer */
    size_t size;
    hk_Error err;
} Io;

static int convert_tfx(void *user)
{
    Io *io = user;
    hk_HairFile h;
    if (hk_hair_read(io->in, HK_HAIR_FORMAT_AUTO, &h, &io->err) != HK_OK) return 0;
    const hk_Status st = hk_hair_write(io->out, &h, NULL, &io->err);
    hk_hair_free(&h);
    return st == HK_OK;
}

static int save_hair(void *user)
{
    Io *io = user;
    return hk_hair_save(io->out, &io->hair, &io->err) == HK_OK;
}

static int load_hair(void *user)
{
    Io *io = user;
    hk_HairFile h;
    if (hk_hair_load(io->out, &h, &io->err) != HK_OK) return 0;
    hk_hair_free(&h);
    return 1;
}

/* The same bytes with stdio alone: fwrite, then fflush and fsync as hk_hair_save does
 * (it writes atomically: a temporary file synced, then renamed). */
static int plain_write(void *user)
{
    Io *io = user;
    FILE *fp = fopen(io->in, "wb");
    if (!fp) return 0;
    int ok = fwrite(io->bytes, 1, io->size, fp) == io->size;
    ok = ok && fflush(fp) == 0 && fsync(fileno(fp)) == 0;
    return fclose(fp) == 0 && ok;
}

/* Into fresh memory, as any reader must (hk_hair_load allocates its arrays). */
static int plain_read(void *user)
{
    Io *io = user;
    FILE *fp = fopen(io->in, "rb");
    unsigned char *buf = malloc(io->size);
    const int ok = fp && buf && fread(buf, 1, io->size, fp) == io->size;
    free(buf);
    if (fp) fclose(fp);
    return ok;
}

/* Into the same buffer every time (its pages already mapped): the floor. */
static int plain_read_warm(void *user)
{
    Io *io = user;
    FILE *fp = fopen(io->in, "rb");
    if (!fp) return 0;
    const int ok = fread(io->bytes, 1, io->size, fp) == io->size;
    fclose(fp);
    return ok;
}

/* A groom of `strands` strands of `points` points (each a wavy line), hairkit's own
 * layout: segments and points arrays. */
static int make_groom(hk_HairFile *h, uint32_t strands, uint32_t points, hk_Error *err)
{
    uint32_t *counts = malloc(sizeof *counts * strands);
    if (!counts) return 0;
    for (uint32_t s = 0; s < strands; s++) counts[s] = points;
    const hk_Status st = hk_hair_alloc(h, strands, counts, err);
    free(counts);
    if (st != HK_OK) return 0;
    for (uint32_t s = 0; s < strands; s++) {
        const double a = 2.0 * HK_PI * (double)s / strands, x = 0.1 * cos(a), z = 0.1 * sin(a);
        for (uint32_t p = 0; p < points; p++) {
            float *q = h->points + 3 * ((size_t)s * points + p);
            q[0] = (float)(x + 0.003 * sin(0.7 * p + a)), q[1] = (float)(1.7 - 0.01 * p), q[2] = (float)z;
        }
    }
    h->default_thickness = 7e-5f;
    return 1;
}

int hk_bench_io(FILE *out, const hk_BenchOptions *options)
{
    const int reps = options->quick ? 1 : 5;
    char in[4096], path[4096], plain[4096];
    const char *tmp = getenv("TMPDIR");
    snprintf(path, sizeof path, "%s/hairkit-bench-io-%ld.hair", tmp && *tmp ? tmp : "/tmp", (long)getpid());
    snprintf(plain, sizeof plain, "%s/hairkit-bench-io-%ld.bin", tmp && *tmp ? tmp : "/tmp", (long)getpid());
    Io io;
    memset(&io, 0, sizeof io);
    int rc = 0;

    /* 1. Sintel's TressFX groom to .hair. */
    snprintf(in, sizeof in, "%s/../shared/hair-data/SintelHairOriginal-sintel_hair.16points.tfx", options->root);
    struct stat sb;
    fprintf(out, "io: hair files (best of %d; the file system's cache is warm)\n", reps);
    if (stat(in, &sb) != 0) {
        fprintf(out, "  Sintel .tfx -> .hair: skipped, %s is absent (../shared/hair-data)\n", in);
    } else {
        io.in = in, io.out = path;
        const double t = best_of(reps, convert_tfx, &io);
        if (t < 0) {
            fprintf(stderr, "bench io: %s\n", io.err.message);
            rc = 1;
        } else {
            fprintf(out, "  Sintel .tfx -> .hair (11,400 strands x 16 points, %.1f MB): %.1f ms (aim: < 50 ms)\n",
                    (double)sb.st_size / 1e6, 1e3 * t);
        }
    }

    /* 2. A large groom written and read as .hair, against stdio moving its bytes. */
    const uint32_t strands = options->quick ? 10000 : 1000000, points = 32;
    if (!rc && !make_groom(&io.hair, strands, points, &io.err)) {
        fprintf(stderr, "bench io: %s\n", io.err.message);
        rc = 1;
    }
    if (!rc) {
        io.in = plain, io.out = path;
        io.size = 128 + 2 * (size_t)strands + 12 * (size_t)strands * points;
        io.bytes = malloc(io.size);
        if (!io.bytes)
            rc = 1;
        else
            memset(io.bytes, 0x3c, io.size);
    }
    if (!rc) {
        const double ws = best_of(reps, save_hair, &io), wp = best_of(reps, plain_write, &io);
        const double rs = best_of(reps, load_hair, &io), rp = best_of(reps, plain_read, &io);
        const double rw = best_of(reps, plain_read_warm, &io);
        if (ws < 0 || rs < 0 || wp < 0 || rp < 0 || rw < 0) {
            fprintf(stderr, "bench io: %s\n", ws < 0 || rs < 0 ? io.err.message : "plain stdio failed");
            rc = 1;
        } else {
            fprintf(out, "  %u strands x %u points (%.0f MB):  hairkit .hair   stdio, same bytes   ratio (aim <= 2)\n",
                    strands, points, (double)io.size / 1e6);
            fprintf(out, "    write (hk_hair_save / fwrite + fsync) %8.1f ms %12.1f ms %10.2f\n", 1e3 * ws, 1e3 * wp,
                    ws / wp);
            fprintf(out, "    read  (hk_hair_load / malloc + fread) %8.1f ms %12.1f ms %10.2f\n", 1e3 * rs, 1e3 * rp,
                    rs / rp);
            fprintf(
                out,
                "    (fread into memory already mapped: %.1f ms; most of a read is the kernel mapping fresh pages)\n",
                1e3 * rw);
        }
    }
    hk_hair_free(&io.hair);
    free(io.bytes);
    unlink(path);
    unlink(plain);
    return rc;
}
