/* Shading of the hair's vertices (as the thesis's vertex shader prepares t, l and e,
 * §4.1.5): the tangent from the neighbouring points, the light through the head's
 * shadow and the hair's deep opacity map (§4.1.6), and Kajiya-Kay or Marschner.
 *
 * Vertices are shaded lazily, when a segment is first drawn: most segments of a full
 * head lie behind saturated pixels and are never drawn. Each vertex has a state
 * (new, being shaded, done); the thread that moves it from new to being shaded shades
 * and publishes it, a thread that finds it being shaded shades its own copy. The value
 * does not depend on who computes it, so the picture does not depend on the threads. */
#include <stdlib.h>

#include "render_internal.h"
#include "shading.h"

hk_Status hk_hair_shader_init(hk_HairShader *s, const hk_Scene *sc, const uint8_t *segment_start,
                              const hk_LightMaps *maps, const hk_View *camera, hk_Error *err)
{
    s->scene = sc, s->segment_start = segment_start, s->maps = maps, s->camera = camera;
    s->marschner = hk_marschner_params_from_color(sc->vis->diffuse);
    s->ambient = hk_v3_scale(sc->vis->ambient, sc->opt->ambient_intensity);
    s->ambient_light = 2.0 * sc->opt->ambient_intensity; /* as the skin's (tile_head.c) */
    if (sc->opt->scattering == HK_SCATTERING_DUAL &&
        !(s->dual_ready && hk_v3_dist(s->dual_colour, sc->vis->diffuse) == 0.0)) {
        hk_dual_scattering_init(&s->marschner, &s->dual);
        s->dual_colour = sc->vis->diffuse, s->dual_ready = 1;
    }
    const size_t n = sc->hair->point_count ? sc->hair->point_count : 1;
    const size_t kept = s->colour_cap;
    if (!HK_RESERVE(s->colour, s->colour_cap, n, err) || !HK_RESERVE(s->strand_of, s->strand_of_cap, n, err)) {
        hk_hair_shader_free(s);
        return HK_ERR_NOMEM;
    }
    /* Two new state values (4 bytes of every vertex's 16 written only for new memory or
     * after 2^31 pictures, rather than every picture). */
    if (s->colour_cap != kept || s->done > UINT32_MAX - 2) {
        hk_VertexColour *c = s->colour;
#pragma omp parallel for schedule(static) num_threads(sc->threads)
        for (long i = 0; i < (long)s->colour_cap; i++) atomic_init(&c[i].state, 0);
        s->done = 0;
    }
    s->busy = s->done + 1, s->done += 2;
    /* Strands of one length (a groom's, a simulated frame's): a vertex's strand is its
     * index divided by the length, with no table to fill and to read (a cache miss per
     * vertex shaded, the vertices being reached in depth order). */
    const hk_HairFile *h = sc->hair;
    const uint32_t len = h->strand_count > 0 ? h->first_point[1] - h->first_point[0] : 0;
    int uniform = len > 0;
    for (uint32_t k = 0; uniform && k <= h->strand_count; k++)
        uniform = (uint64_t)h->first_point[k] == (uint64_t)k * len;
    s->strand_length = uniform ? len : 0;
    if (uniform) return HK_OK;
#pragma omp parallel for schedule(static) num_threads(sc->threads)
    for (long k = 0; k < (long)h->strand_count; k++)
        for (uint32_t i = h->first_point[k]; i < h->first_point[k + 1]; i++) s->strand_of[i] = (uint32_t)k;
    return HK_OK;
}

void hk_hair_shader_free(hk_HairShader *s)
{
    hk_free(s->colour);
    hk_free(s->strand_of);
    s->colour = NULL, s->strand_of = NULL;
    s->colour_cap = s->strand_of_cap = 0;
    s->busy = s->done = 0;
    s->dual_ready = 0;
}

/* A number in [-1, 1) from a strand's index (splitmix64 finaliser). */
static double strand_jitter(uint32_t strand)
{
    uint64_t z = (uint64_t)strand + 0x9E3779B97F4A7C15ull;
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    z ^= z >> 31;
    return (double)(z >> 11) * (2.0 / 9007199254740992.0) - 1.0;
}

static void shade(const hk_HairShader *s, uint32_t i, float out[3])
{
    const hk_Scene *sc = s->scene;
    const hk_HairFile *h = sc->hair;
    const hk_RenderDef *o = sc->opt;
    const int has_next = s->segment_start[i], has_prev = i > 0 && s->segment_start[i - 1];
    hk_Vec3 t = hk_v3_sub(hk_hair_point(h, has_next ? i + 1 : i), hk_hair_point(h, has_prev ? i - 1 : i));
    const double length = hk_v3_norm(t); /* hk_v3_normalize's, once */
    t = length > 0.0 ? hk_v3_scale(t, 1.0 / length) : hk_v3(0, 1, 0);
    const hk_Vec3 p = hk_hair_point(h, i);
    const hk_Vec3 e = hk_v3_normalize(hk_v3_sub(s->camera->origin, p));
    double head_visible = 1.0, opacity = 0.0;
    if (s->maps) hk_light_lookup(s->maps, p, &head_visible, &opacity);
    hk_Visuality v = *sc->vis;
    if (h->colors)
        v.diffuse = hk_srgb_to_linear(
            hk_v3(h->colors[3 * (size_t)i], h->colors[3 * (size_t)i + 1], h->colors[3 * (size_t)i + 2]));
    hk_Vec3 c;
    if (o->scattering == HK_SCATTERING_DUAL) {
        /* Dual scattering (dual_scattering.c): the light through the `opacity` fibres in
         * front, unscattered and forward-scattered, and the neighbours' backscattering;
         * the head's shadow stops all of it. The ambient light is reflected by the hair
         * as a whole, with the colour of hair lit from all around: DiffuseColor (what
         * Chiang et al.'s mapping makes of it for the fibre). */
        /* Marschner's S is per steradian; the renderer's unit light gives a Lambert
         * surface of albedo rho the radiance rho cos (the skin, tile_head.c), which is
         * an irradiance of pi: S is scaled by pi to match (without the Kajiya-Kay
         * stand-in of single scattering, whose K_d sin is in those units, the lobes
         * alone would be a third as bright as the skin of the same albedo). */
        const hk_Vec3 lit = o->shading == HK_SHADING_MARSCHNER
                                ? hk_v3_scale(hk_shade_dual_marschner(&s->dual, t, sc->light_dir, e, opacity), HK_PI)
                                : hk_shade_dual_kajiya_kay(&s->dual, t, sc->light_dir, e, opacity, &v);
        c = hk_v3_madd(hk_v3_madd(s->ambient, v.diffuse, s->ambient_light), lit, o->light_intensity * head_visible);
    } else {
        const double visible = head_visible * (o->scatter_floor + (1.0 - o->scatter_floor) * exp(-opacity));
        hk_Vec3 lit;
        if (o->shading == HK_SHADING_MARSCHNER) {
            /* Marschner's lobes are single scattering; the colour of brown and blond
             * hair comes mostly from light scattered through many fibres, which
             * Kajiya-Kay's diffuse term stands in for (as production Marschner shaders
             * do). */
            const double tl = hk_v3_dot(t, sc->light_dir), sin_tl = sqrt(fmax(0.0, 1.0 - tl * tl));
            lit = hk_v3_madd(hk_shade_marschner(t, sc->light_dir, e, &s->marschner), v.diffuse, sin_tl);
        } else {
            lit = hk_shade_kajiya_kay(t, sc->light_dir, e, &v);
        }
        c = hk_v3_madd(s->ambient, lit, o->light_intensity * visible);
    }
    /* Real hairs differ slightly in colour; a fixed brightness per strand (from a hash
     * of its index, so the same on every run) keeps a full head from looking painted. */
    if (o->strand_variation > 0.0) {
        const uint32_t strand = s->strand_length ? i / s->strand_length : s->strand_of[i];
        c = hk_v3_scale(c, 1.0 + o->strand_variation * strand_jitter(strand));
    }
    out[0] = (float)c.x, out[1] = (float)c.y, out[2] = (float)c.z;
}

void hk_hair_shader_get(hk_HairShader *s, uint32_t i, float out[3])
{
    hk_VertexColour *c = &s->colour[i];
    unsigned state = atomic_load_explicit(&c->state, memory_order_acquire);
    if (state == s->done) {
        out[0] = c->rgb[0], out[1] = c->rgb[1], out[2] = c->rgb[2];
        return;
    }
    shade(s, i, out);
    unsigned expected = state;
    if (state != s->busy && atomic_compare_exchange_strong_explicit(&c->state, &expected, s->busy, memory_order_acq_rel,
                                                                    memory_order_acquire)) {
        c->rgb[0] = out[0], c->rgb[1] = out[1], c->rgb[2] = out[2];
        atomic_store_explicit(&c->state, s->done, memory_order_release);
    }
}

hk_Vec3 hk_srgb_to_linear(hk_Vec3 c)
{
    double v[3] = {c.x, c.y, c.z};
    for (int k = 0; k < 3; k++) {
        const double x = v[k];
        v[k] = x <= 0.04045 ? x / 12.92 : pow((x + 0.055) / 1.055, 2.4); /* IEC 61966-2-1 */
    }
    return hk_v3(v[0], v[1], v[2]);
}
