/* Generates assets/head.obj (a human head with neck) and assets/wick.obj (the scalp
 * the hair grows from) from an implicit model, so that the assets can be remade and
 * changed. Usage: make_assets OUTDIR.
 *
 * The head is a smooth union of ellipsoids and a capsule (cranium, face, jaw, nose,
 * brow, cheeks, lips, ears, neck) minus eye sockets. Its cranium is exactly the head
 * ellipsoid of the thesis's hair coupes (Lansink 2010 Appendix C: centre (-0.001, 0.068,
 * 0.010), semi-axes 0.08, 0.08, 0.11), so the collision files of the thesis fit it.
 * y is up, the face looks along +z, units are metres. The surface is star-shaped from
 * a point inside the head: every vertex is the outermost crossing of the surface along
 * a ray from that point, found by marching and bisection. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "hairkit/mesh.h"

typedef struct Blob {
    hk_Vec3 c, r;
} Blob;

static const hk_Vec3 cranium_c = {-0.001, 0.068, 0.010}, cranium_r = {0.080, 0.080, 0.110};

static const Blob features[] = {
    {{0.0, 0.005, 0.050}, {0.062, 0.085, 0.072}},                                                    /* face and jaw */
    {{0.0, -0.055, 0.075}, {0.035, 0.030, 0.035}},                                                   /* chin */
    {{0.0, 0.030, 0.122}, {0.011, 0.026, 0.020}},                                                    /* nose */
    {{0.0, 0.064, 0.098}, {0.052, 0.011, 0.028}},                                                    /* brow */
    {{0.045, 0.022, 0.085}, {0.025, 0.020, 0.030}},                                                  /* cheekbones */
    {{-0.045, 0.022, 0.085}, {0.025, 0.020, 0.030}}, {{0.0, -0.028, 0.110}, {0.024, 0.009, 0.012}},  /* lips */
    {{0.079, 0.035, 0.000}, {0.013, 0.032, 0.020}},                                                  /* ears */
    {{-0.080, 0.035, 0.000}, {0.013, 0.032, 0.020}}, {{0.033, 0.042, 0.106}, {0.013, 0.013, 0.013}}, /* eyeballs */
    {{-0.033, 0.042, 0.106}, {0.013, 0.013, 0.013}},
};
static const Blob sockets[] = {
    {{0.033, 0.045, 0.122}, {0.017, 0.014, 0.014}},
    {{-0.033, 0.045, 0.122}, {0.017, 0.014, 0.014}},
};

/* Approximate signed distance to an ellipsoid: exact for a sphere, the right sign
 * everywhere, zero exactly on the surface. */
static double ellipsoid_sd(hk_Vec3 p, hk_Vec3 c, hk_Vec3 r)
{
    hk_Vec3 q = hk_v3((p.x - c.x) / r.x, (p.y - c.y) / r.y, (p.z - c.z) / r.z);
    return (hk_v3_norm(q) - 1.0) * fmin(r.x, fmin(r.y, r.z));
}

/* Polynomial smooth minimum: equal to min(a, b) where |a - b| >= k. */
static double smin(double a, double b, double k)
{
    double h = fmax(k - fabs(a - b), 0.0) / k;
    return fmin(a, b) - 0.25 * h * h * k;
}

static double head_sd(hk_Vec3 p)
{
    double d = ellipsoid_sd(p, cranium_c, cranium_r);
    for (size_t i = 0; i < sizeof features / sizeof *features; i++)
        d = smin(d, ellipsoid_sd(p, features[i].c, features[i].r), i >= 9 ? 0.004 : 0.012);
    /* Neck: a vertical capsule from the chin's height down to the shoulders. */
    double y = fmin(fmax(p.y, -0.16), -0.01);
    double neck = hk_v3_norm(hk_v3_sub(p, hk_v3(0.0, y, -0.015))) - 0.049;
    d = smin(d, neck, 0.03);
    for (size_t i = 0; i < sizeof sockets / sizeof *sockets; i++)
        d = -smin(-d, ellipsoid_sd(p, sockets[i].c, sockets[i].r), 0.006);
    return d;
}

static const hk_Vec3 centre = {0.0, 0.02, 0.01};

/* Outermost crossing of the surface along the ray from the centre. */
static hk_Vec3 surface_along(hk_Vec3 dir)
{
    dir = hk_v3_normalize(dir);
    double outside = 0.45, t = outside;
    while (t > 0.0 && head_sd(hk_v3_madd(centre, dir, t)) > 0.0) outside = t, t -= 0.0015;
    double inside = t > 0.0 ? t : 0.0;
    for (int i = 0; i < 60; i++) {
        double mid = 0.5 * (inside + outside);
        if (head_sd(hk_v3_madd(centre, dir, mid)) > 0.0)
            outside = mid;
        else
            inside = mid;
    }
    return hk_v3_madd(centre, dir, 0.5 * (inside + outside));
}

static hk_Vec3 surface_normal(hk_Vec3 p)
{
    const double h = 1e-6;
    hk_Vec3 g = hk_v3_zero();
    for (int i = 0; i < 3; i++) {
        hk_Vec3 a = p, b = p;
        hk_v3_set(&a, i, hk_v3_get(p, i) + h);
        hk_v3_set(&b, i, hk_v3_get(p, i) - h);
        hk_v3_set(&g, i, head_sd(a) - head_sd(b));
    }
    return hk_v3_normalize(g);
}

/* Outward orientation: flip triangles whose normal opposes the surface normals. */
static void orient_outwards(hk_Mesh *m)
{
    for (int t = 0; t < m->triangle_count; t++) {
        int *tri = m->triangles + 3 * t;
        hk_Vec3 a = m->positions[tri[0]], b = m->positions[tri[1]], c = m->positions[tri[2]];
        hk_Vec3 n = hk_v3_cross(hk_v3_sub(b, a), hk_v3_sub(c, a));
        hk_Vec3 outward = hk_v3_add(m->normals[tri[0]], hk_v3_add(m->normals[tri[1]], m->normals[tri[2]]));
        if (hk_v3_dot(n, outward) < 0.0) {
            int s = tri[1];
            tri[1] = tri[2];
            tri[2] = s;
        }
    }
}

/* Head: rings of constant polar angle around the vertical through the centre. */
static int make_head(hk_Mesh *m, hk_Error *err)
{
    const int rings = 80, segments = 96;
    const int nv = 2 + (rings - 1) * segments, nt = 2 * segments * (rings - 1);
    if (hk_mesh_alloc(m, nv, nt, err) != HK_OK) return 0;
    const double pi = HK_PI;
    int v = 0;
    m->positions[v++] = surface_along(hk_v3(0, 1, 0));
    for (int i = 1; i < rings; i++) {
        const double theta = pi * i / rings;
        for (int j = 0; j < segments; j++) {
            double phi = 2 * pi * j / segments;
            m->positions[v++] = surface_along(hk_v3(sin(theta) * sin(phi), cos(theta), sin(theta) * cos(phi)));
        }
    }
    m->positions[v++] = surface_along(hk_v3(0, -1, 0));
    int t = 0;
    for (int j = 0; j < segments; j++) {
        int a = 1 + j, b = 1 + (j + 1) % segments;
        int *tri = m->triangles + 3 * t++;
        tri[0] = 0, tri[1] = a, tri[2] = b;
    }
    for (int i = 1; i < rings - 1; i++)
        for (int j = 0; j < segments; j++) {
            int a = 1 + (i - 1) * segments + j, b = 1 + (i - 1) * segments + (j + 1) % segments;
            int c = a + segments, d = b + segments;
            int *t1 = m->triangles + 3 * t++, *t2 = m->triangles + 3 * t++;
            t1[0] = a, t1[1] = c, t1[2] = b;
            t2[0] = b, t2[1] = c, t2[2] = d;
        }
    const int last = nv - 1, base = 1 + (rings - 2) * segments;
    for (int j = 0; j < segments; j++) {
        int *tri = m->triangles + 3 * t++;
        tri[0] = last, tri[1] = base + (j + 1) % segments, tri[2] = base + j;
    }
    for (int i = 0; i < nv; i++) m->normals[i] = surface_normal(m->positions[i]);
    orient_outwards(m);
    return 1;
}

/* Polar angle (from the crown, in the cranium's normalised coordinates) of the
 * hairline at azimuth phi (0 = forehead): 63 degrees at the forehead, about 85 above
 * the ears, 125 at the nape. */
static double hairline(double phi)
{
    const double pi = HK_PI, w = 0.5 * (1.0 - cos(phi));
    return (63.0 + 62.0 * pow(w, 1.5)) * pi / 180.0;
}

/* Wick: a crown vertex and rings out to the hairline, projected onto the head. */
static int make_wick(hk_Mesh *m, int rings, int segments, hk_Error *err)
{
    const int nv = 1 + rings * segments, nt = segments + 2 * segments * (rings - 1);
    if (hk_mesh_alloc(m, nv, nt, err) != HK_OK) return 0;
    const double pi = HK_PI;
    for (int v = 0; v < nv; v++) {
        double theta = 0.0, phi = 0.0;
        if (v > 0) {
            int i = 1 + (v - 1) / segments, j = (v - 1) % segments;
            /* Stagger alternate rings by half a segment: better-shaped triangles. */
            phi = 2 * pi * (j + 0.5 * (i % 2)) / segments;
            theta = hairline(phi) * i / rings;
        }
        hk_Vec3 u = hk_v3(sin(theta) * sin(phi), cos(theta), sin(theta) * cos(phi));
        hk_Vec3 on_cranium =
            hk_v3(cranium_c.x + cranium_r.x * u.x, cranium_c.y + cranium_r.y * u.y, cranium_c.z + cranium_r.z * u.z);
        m->positions[v] = surface_along(hk_v3_sub(on_cranium, centre));
        m->normals[v] = surface_normal(m->positions[v]);
    }
    int t = 0;
    for (int j = 0; j < segments; j++) {
        int *tri = m->triangles + 3 * t++;
        tri[0] = 0, tri[1] = 1 + j, tri[2] = 1 + (j + 1) % segments;
    }
    for (int i = 1; i < rings; i++)
        for (int j = 0; j < segments; j++) {
            int a = 1 + (i - 1) * segments + j, b = 1 + (i - 1) * segments + (j + 1) % segments;
            /* Ring i+1 is shifted by half a segment relative to ring i (or back). */
            int c = a + segments, d = b + segments;
            int *t1 = m->triangles + 3 * t++, *t2 = m->triangles + 3 * t++;
            if (i % 2) { /* a (shifted) lies between c and d */
                t1[0] = a, t1[1] = c, t1[2] = d;
                t2[0] = a, t2[1] = d, t2[2] = b;
            } else { /* c (shifted) lies between a and b */
                t1[0] = a, t1[1] = c, t1[2] = b;
                t2[0] = b, t2[1] = c, t2[2] = d;
            }
        }
    orient_outwards(m);
    return 1;
}

int main(int argc, char **argv)
{
    if (argc != 2) {
        fprintf(stderr, "usage: make_assets OUTDIR\n");
        return 2;
    }
    char path[4096];
    hk_Error err;
    hk_Mesh head, wick, wick200;
    /* wick-200: the same scalp with half the rings, 201 guides (the dynamics benchmark
     * and examples/guides200: Bertails et al. 2006 simulates 100-200 guides). */
    if (!make_head(&head, &err) || !make_wick(&wick, 10, 40, &err) || !make_wick(&wick200, 5, 40, &err)) {
        fprintf(stderr, "make_assets: %s\n", err.message);
        return 1;
    }
    snprintf(path, sizeof path, "%s/head.obj", argv[1]);
    if (hk_obj_save(path, &head, "hairkit head with neck, generated by tools/make_assets.c (MIT licence)", &err)) {
        fprintf(stderr, "make_assets: %s\n", err.message);
        return 1;
    }
    snprintf(path, sizeof path, "%s/wick.obj", argv[1]);
    if (hk_obj_save(path, &wick, "hairkit scalp wick, generated by tools/make_assets.c (MIT licence)", &err)) {
        fprintf(stderr, "make_assets: %s\n", err.message);
        return 1;
    }
    snprintf(path, sizeof path, "%s/wick-200.obj", argv[1]);
    if (hk_obj_save(path, &wick200,
                    "hairkit scalp wick with 201 guides, generated by tools/make_assets.c (MIT licence)", &err)) {
        fprintf(stderr, "make_assets: %s\n", err.message);
        return 1;
    }
    printf("head: %d vertices, %d triangles; wick: %d vertices (guides), %d triangles, %.1f cm^2\n", head.vertex_count,
           head.triangle_count, wick.vertex_count, wick.triangle_count, 1e4 * hk_mesh_area(&wick));
    hk_mesh_free(&head);
    hk_mesh_free(&wick);
    hk_mesh_free(&wick200);
    return 0;
}
