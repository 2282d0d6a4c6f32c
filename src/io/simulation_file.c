/* The simulation manifest DIR/simulation.txt (docs/file-formats.md): `Key value` lines
 * like the thesis's files, read with file:line errors, written atomically. */
#include <errno.h>
#include <inttypes.h>
#include <stdlib.h>
#include <string.h>

#include "hairkit/motion.h"
#include "io/io_internal.h"
#include "io/outfile.h"
#include "hairkit/simulation_file.h"
#include "keyfile.h"

enum {
    M_FORMAT,
    M_SETUP,
    M_SEED,
    M_FRAMES,
    M_FPS,
    M_GUIDES,
    M_POINTS,
    M_INTERPOLATED,
    M_FULL_HAIR,
    M_HAIRSTYLE_HASH,
    M_WICK_HASH,
    M_COLLISION_HASH,
    M_MOTION,
    M_MOTION_FILE,
    M_MOTION_HASH,
    M_COUNT
};

static const hk_KeySpec specs[M_COUNT] = {
    [M_FORMAT] = {"HairkitSimulation", NULL, 1},
    [M_SETUP] = {"Setup", NULL, 1},
    [M_SEED] = {"Seed", NULL, 1},
    [M_FRAMES] = {"Frames", NULL, 1},
    [M_FPS] = {"Fps", NULL, 1},
    [M_GUIDES] = {"Guides", NULL, 1},
    [M_POINTS] = {"PointsPerStrand", NULL, 1},
    [M_INTERPOLATED] = {"Interpolated", NULL, 1},
    [M_FULL_HAIR] = {"FullHair", NULL, 1},
    [M_HAIRSTYLE_HASH] = {"HairstyleHash", NULL, 1},
    [M_WICK_HASH] = {"WickHash", NULL, 1},
    /* not required by the key check: format 1 has none, and the motion is one of two */
    [M_COLLISION_HASH] = {"CollisionHash", NULL, 0},
    [M_MOTION] = {"Motion", NULL, 0},
    [M_MOTION_FILE] = {"MotionFile", NULL, 0},
    [M_MOTION_HASH] = {"MotionHash", NULL, 0},
};

void hk_simulation_manifest_free(hk_SimulationManifest *m)
{
    hk_free(m->setup);
    hk_free(m->motion_script);
    hk_free(m->motion_file);
    memset(m, 0, sizeof *m);
}

hk_Status hk_file_fingerprint_more(const char *path, uint64_t *hash, hk_Error *err)
{
    FILE *fp = fopen(path, "rb");
    if (!fp) return hk_error_set(err, HK_ERR_IO, "%s: cannot read: %s", path, strerror(errno));
    uint64_t h = *hash;
    unsigned char buf[65536];
    size_t n;
    while ((n = fread(buf, 1, sizeof buf, fp)) > 0)
        for (size_t i = 0; i < n; i++) h = (h ^ buf[i]) * 0x100000001b3ull;
    const int bad = ferror(fp);
    fclose(fp);
    if (bad) return hk_error_set(err, HK_ERR_IO, "%s: read error", path);
    *hash = h;
    return HK_OK;
}

hk_Status hk_file_fingerprint(const char *path, uint64_t *out, hk_Error *err)
{
    *out = 0xcbf29ce484222325ull; /* FNV-1a 64's offset basis */
    return hk_file_fingerprint_more(path, out, err);
}

/* 1 to 16 hex digits, nothing else. */
static hk_Status read_hash(const hk_KeyFile *kf, const hk_KeyLine *kl, uint64_t *out, hk_Error *err)
{
    const char *v;
    hk_Status st = hk_keyline_string(kf, kl, &v, err);
    if (st != HK_OK) return st;
    const size_t n = strlen(v);
    if (n == 0 || n > 16 || strspn(v, "0123456789abcdefABCDEF") != n)
        return hk_keyfile_error(kf, kl->line, HK_ERR_PARSE, err, "%s expects up to 16 hex digits, got '%s'", kl->key,
                                v);
    *out = strtoull(v, NULL, 16);
    return HK_OK;
}

/* Motion NAME AMPLITUDE FREQUENCY PX PY PZ */
static hk_Status read_motion(const hk_KeyFile *kf, const hk_KeyLine *kl, hk_SimulationManifest *m, hk_Error *err)
{
    if (kl->count != 6)
        return hk_keyfile_error(kf, kl->line, HK_ERR_PARSE, err,
                                "Motion expects NAME AMPLITUDE FREQUENCY PIVOT_X PIVOT_Y PIVOT_Z, got %d values",
                                kl->count);
    const hk_KeyLine numbers = {kl->line, kl->key, 5, kl->values + 1};
    double v[5];
    hk_Status st = hk_keyline_doubles(kf, &numbers, 5, v, err);
    if (st != HK_OK) return st;
    /* A motion the rebuild could not make again is refused here, at its line. */
    hk_HeadMotion *probe = NULL;
    hk_Error why;
    if (hk_head_motion_scripted(kl->values[0], v[0], v[1], hk_v3(v[2], v[3], v[4]), &probe, &why) != HK_OK)
        return hk_keyfile_error(kf, kl->line, HK_ERR_INVALID, err, "%s", why.message);
    hk_head_motion_destroy(probe);
    m->motion_script = hk_strdup(kl->values[0], err);
    if (!m->motion_script) return HK_ERR_NOMEM;
    m->motion_amplitude = v[0];
    m->motion_frequency = v[1];
    for (int i = 0; i < 3; i++) m->motion_pivot[i] = v[2 + i];
    return HK_OK;
}

/* The motion is given once, as a script or as a file with its fingerprint. */
static hk_Status check_motion(const hk_KeyFile *kf, const int *line_of, hk_Error *err)
{
    if (line_of[M_MOTION] && line_of[M_MOTION_FILE])
        return hk_keyfile_error(kf, line_of[M_MOTION_FILE], HK_ERR_PARSE, err,
                                "MotionFile and Motion (line %d) exclude each other", line_of[M_MOTION]);
    if (!line_of[M_MOTION] && !line_of[M_MOTION_FILE])
        return hk_keyfile_error(kf, 0, HK_ERR_PARSE, err, "missing required key 'Motion' (or 'MotionFile')");
    if (!line_of[M_MOTION_FILE] != !line_of[M_MOTION_HASH])
        return hk_keyfile_error(kf, line_of[M_MOTION_FILE] ? line_of[M_MOTION_FILE] : line_of[M_MOTION_HASH],
                                HK_ERR_PARSE, err, "MotionFile and MotionHash go together");
    return HK_OK;
}

static hk_Status read_line(const hk_KeyFile *kf, const hk_KeyLine *kl, int k, hk_SimulationManifest *m, hk_Error *err)
{
    long n = 0;
    hk_Status st = HK_OK;
    const char *s;
    switch (k) {
    case M_FORMAT:
        if ((st = hk_keyline_int(kf, kl, 1, HK_SIMULATION_FILE_VERSION, &n, err)) == HK_OK) m->version = (int)n;
        if (st == HK_ERR_INVALID)
            return hk_keyfile_error(kf, kl->line, HK_ERR_PARSE, err,
                                    "a simulation of format %s: this hairkit reads format %d", kl->values[0],
                                    HK_SIMULATION_FILE_VERSION);
        if (st == HK_OK && n < HK_SIMULATION_FILE_VERSION)
            return hk_keyfile_error(kf, kl->line, HK_ERR_PARSE, err,
                                    "a simulation of format %ld, whose frames did not keep the hair out of the "
                                    "moving body: this hairkit reads format %d, simulate again",
                                    n, HK_SIMULATION_FILE_VERSION);
        return st;
    case M_SETUP:
        if ((st = hk_keyline_string(kf, kl, &s, err)) != HK_OK) return st;
        m->setup = hk_keyfile_resolve_path(kf, s, err);
        return m->setup ? HK_OK : HK_ERR_NOMEM;
    case M_SEED:
        if ((st = hk_keyline_string(kf, kl, &s, err)) != HK_OK) return st;
        errno = 0;
        char *end;
        m->seed = strtoull(s, &end, 10);
        if (!*s || *end || errno || s[0] == '-')
            return hk_keyfile_error(kf, kl->line, HK_ERR_PARSE, err, "Seed expects a non-negative integer, got '%s'",
                                    s);
        return HK_OK;
    case M_FRAMES:
        return hk_keyline_int(kf, kl, 1, 100000, &m->frames, err);
    case M_FPS:
        if ((st = hk_keyline_doubles(kf, kl, 1, &m->fps, err)) != HK_OK) return st;
        if (!(m->fps > 0.0))
            return hk_keyfile_error(kf, kl->line, HK_ERR_INVALID, err, "Fps must be > 0, got %g", m->fps);
        return HK_OK;
    case M_GUIDES:
        if ((st = hk_keyline_int(kf, kl, 1, 100000000, &n, err)) == HK_OK) m->guides = (int)n;
        return st;
    case M_POINTS:
        if ((st = hk_keyline_int(kf, kl, 2, 65536, &n, err)) == HK_OK) m->points = (int)n;
        return st;
    case M_INTERPOLATED:
        return hk_keyline_bool(kf, kl, &m->interpolated, err);
    case M_FULL_HAIR:
        return hk_keyline_bool(kf, kl, &m->full_hair, err);
    case M_HAIRSTYLE_HASH:
        return read_hash(kf, kl, &m->hairstyle_hash, err);
    case M_WICK_HASH:
        return read_hash(kf, kl, &m->wick_hash, err);
    case M_COLLISION_HASH:
        m->has_collision = 1;
        return read_hash(kf, kl, &m->collision_hash, err);
    case M_MOTION:
        return read_motion(kf, kl, m, err);
    case M_MOTION_FILE:
        if ((st = hk_keyline_string(kf, kl, &s, err)) != HK_OK) return st;
        m->motion_file = hk_keyfile_resolve_path(kf, s, err);
        return m->motion_file ? HK_OK : HK_ERR_NOMEM;
    case M_MOTION_HASH:
        return read_hash(kf, kl, &m->motion_hash, err);
    default:
        return HK_OK;
    }
}

hk_Status hk_simulation_manifest_load(const char *path, hk_SimulationManifest *out, hk_Error *err)
{
    memset(out, 0, sizeof *out);
    hk_KeyFile kf;
    hk_Status st = hk_keyfile_read(path, &kf, err);
    if (st != HK_OK) return st;
    int line_of[M_COUNT];
    st = hk_keyfile_check_keys(&kf, specs, M_COUNT, "simulation", line_of, err);
    for (int i = 0; st == HK_OK && i < kf.line_count; i++) {
        const hk_KeyLine *kl = &kf.lines[i];
        st = read_line(&kf, kl, hk_keyspec_find(specs, M_COUNT, kl->key), out, err);
    }
    if (st == HK_OK) st = check_motion(&kf, line_of, err);
    hk_keyfile_free(&kf);
    if (st != HK_OK) hk_simulation_manifest_free(out);
    return st;
}

hk_Status hk_simulation_manifest_save(const char *path, const hk_SimulationManifest *m, hk_Error *err)
{
    if (!m->setup || strchr(m->setup, '"') || strpbrk(m->setup, "\r\n"))
        return hk_error_set(err, HK_ERR_INVALID, "%s: the setup's path cannot be written in a manifest", path);
    if (!m->motion_script == !m->motion_file)
        return hk_error_set(err, HK_ERR_INVALID, "%s: a manifest needs a scripted motion or a motion file", path);
    if (m->motion_file && (strchr(m->motion_file, '"') || strpbrk(m->motion_file, "\r\n")))
        return hk_error_set(err, HK_ERR_INVALID, "%s: the motion file's path cannot be written in a manifest", path);
    if (m->motion_script && (!*m->motion_script || strpbrk(m->motion_script, " \t\r\n\"#")))
        return hk_error_set(err, HK_ERR_INVALID, "%s: motion '%s' cannot be written in a manifest", path,
                            m->motion_script);
    hk_OutFile out;
    hk_Status st = hk_outfile_open(&out, path, err);
    if (st != HK_OK) return st;
    fprintf(out.fp,
            "# hairkit simulate: what grows the interpolated hair of every frame of this folder again\n"
            "# from DIR/guides_kkkk.hair (hairkit simulate --rebuild DIR --frame K -o OUT.hair).\n"
            "# See docs/file-formats.md, \"Simulation manifest\".\n"
            "HairkitSimulation %d\n"
            "Setup            \"%s\"\n"
            "Seed             %" PRIu64 "\n"
            "Frames           %ld\n"
            "Fps              %.17g\n"
            "Guides           %d\n"
            "PointsPerStrand  %d\n"
            "Interpolated     %s\n"
            "FullHair         %s\n"
            "HairstyleHash    %016" PRIx64 "\n"
            "WickHash         %016" PRIx64 "\n",
            HK_SIMULATION_FILE_VERSION, m->setup, m->seed, m->frames, m->fps, m->guides, m->points,
            m->interpolated ? "true" : "false", m->full_hair ? "true" : "false", m->hairstyle_hash, m->wick_hash);
    if (m->has_collision) fprintf(out.fp, "CollisionHash    %016" PRIx64 "\n", m->collision_hash);
    if (m->motion_script)
        fprintf(out.fp, "Motion           %s %.17g %.17g %.17g %.17g %.17g\n", m->motion_script, m->motion_amplitude,
                m->motion_frequency, m->motion_pivot[0], m->motion_pivot[1], m->motion_pivot[2]);
    else
        fprintf(out.fp, "MotionFile       \"%s\"\nMotionHash       %016" PRIx64 "\n", m->motion_file, m->motion_hash);
    return hk_outfile_commit(&out, err);
}
