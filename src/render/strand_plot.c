/* Orthographic side and front views of strands and collision shapes, for the demo and
 * the documentation pictures (not the hair renderer). */
#include "hairkit/canvas.h"

#include <float.h>
#include <math.h>

typedef struct View {
    int h, v;  /* world axes shown horizontally and vertically */
    int drop;  /* world axis along the line of sight */
    double ox; /* panel's left edge in pixels */
} View;

typedef struct Frame {
    double lo[3], hi[3]; /* world bounds */
    double scale;        /* pixels per metre */
    double margin;
    int height, panel_w;
} Frame;

static double axis_of(hk_Vec3 p, int i) { return hk_v3_get(p, i); }

static void to_screen(const Frame *f, const View *v, hk_Vec3 p, double *x, double *y)
{
    /* Centre the content in the panel; y grows downwards on screen. */
    double cw = (f->hi[v->h] - f->lo[v->h]) * f->scale, ch = (f->hi[v->v] - f->lo[v->v]) * f->scale;
    double x0 = v->ox + 0.5 * (f->panel_w - cw), y0 = 0.5 * (f->height + ch);
    *x = x0 + (axis_of(p, v->h) - f->lo[v->h]) * f->scale;
    *y = y0 - (axis_of(p, v->v) - f->lo[v->v]) * f->scale;
}

static void grow(Frame *f, hk_Vec3 p)
{
    for (int i = 0; i < 3; i++) {
        f->lo[i] = fmin(f->lo[i], axis_of(p, i));
        f->hi[i] = fmax(f->hi[i], axis_of(p, i));
    }
}

/* Half extents of a shape (inflated by `extra`) along the world axes. */
static hk_Vec3 shape_extent(const hk_Shape *s, double extra)
{
    hk_Vec3 e = hk_v3_zero();
    for (int i = 0; i < 3; i++) {
        double acc = 0.0;
        for (int j = 0; j < 3; j++) {
            double r = hk_v3_get(s->half, j) + extra, c = hk_v3_get(s->axis[j], i) * r;
            acc += s->kind == HK_SHAPE_CUBOID ? fabs(c) : c * c;
        }
        hk_v3_set(&e, i, s->kind == HK_SHAPE_CUBOID ? acc : sqrt(acc));
    }
    return e;
}

/* (int)v clamped to [lo, hi] before the conversion (NaN gives lo): a shape of semi-axis
 * 1e308 puts its silhouette's bounds far outside an int. */
static int pixel(double v, int lo, int hi)
{
    if (!(v > lo)) return lo;
    return v < hi ? (int)v : hi;
}

/* Silhouette of an ellipsoid x^T A x <= 1 seen along world axis `drop`: the Schur
 * complement B = A_pp - A_pk A_kp / A_kk is the projected ellipse's matrix. */
static void ellipsoid_silhouette(hk_Canvas *c, const Frame *f, const View *v, const hk_Shape *s, double extra,
                                 hk_Vec3 fill, double fill_alpha, hk_Vec3 line, double width)
{
    double a[3][3] = {{0}};
    for (int j = 0; j < 3; j++) {
        double r = hk_v3_get(s->half, j) + extra;
        if (!(r > 0.0)) return;
        for (int p = 0; p < 3; p++)
            for (int q = 0; q < 3; q++) a[p][q] += hk_v3_get(s->axis[j], p) * hk_v3_get(s->axis[j], q) / (r * r);
    }
    const int h = v->h, vv = v->v, k = v->drop;
    const double b00 = a[h][h] - a[h][k] * a[k][h] / a[k][k];
    const double b01 = a[h][vv] - a[h][k] * a[k][vv] / a[k][k];
    const double b11 = a[vv][vv] - a[vv][k] * a[k][vv] / a[k][k];
    double cx, cy;
    to_screen(f, v, s->centre, &cx, &cy);
    if (fill_alpha > 0.0) {
        const double rx = sqrt(b11 / (b00 * b11 - b01 * b01)) * f->scale + 2;
        const double ry = sqrt(b00 / (b00 * b11 - b01 * b01)) * f->scale + 2;
        for (int y = pixel(cy - ry, 0, c->height); y <= pixel(cy + ry, -1, c->height - 1); y++)
            for (int x = pixel(cx - rx, 0, c->width); x <= pixel(cx + rx, -1, c->width - 1); x++) {
                double dx = (x + 0.5 - cx) / f->scale, dy = -(y + 0.5 - cy) / f->scale;
                if (b00 * dx * dx + 2 * b01 * dx * dy + b11 * dy * dy <= 1.0) {
                    hk_canvas_line(c, x + 0.5, y + 0.5, x + 0.5, y + 0.5, 1.0, fill, fill_alpha);
                }
            }
    }
    /* Boundary by the eigen-decomposition of the 2x2 matrix B. */
    const double tr = b00 + b11, det = b00 * b11 - b01 * b01;
    const double disc = sqrt(fmax(0.0, 0.25 * tr * tr - det));
    const double l1 = 0.5 * tr + disc, l2 = 0.5 * tr - disc;
    double ex = b01, ey = l1 - b00;
    if (fabs(ex) + fabs(ey) < 1e-300) ex = 1.0, ey = 0.0;
    double n = hypot(ex, ey);
    ex /= n, ey /= n;
    double px = 0, py = 0;
    for (int i = 0; i <= 180; i++) {
        double t = 2.0 * HK_PI * i / 180;
        double u = cos(t) / sqrt(l1), w = sin(t) / sqrt(l2);
        double x = cx + (u * ex - w * ey) * f->scale, y = cy - (u * ey + w * ex) * f->scale;
        if (i > 0) hk_canvas_line(c, px, py, x, y, width, line, 1.0);
        px = x, py = y;
    }
}

static void cuboid_outline(hk_Canvas *c, const Frame *f, const View *v, const hk_Shape *s, double extra, hk_Vec3 line,
                           double width)
{
    hk_Vec3 corner[8];
    for (int i = 0; i < 8; i++) {
        hk_Vec3 p = s->centre;
        for (int j = 0; j < 3; j++)
            p = hk_v3_madd(p, s->axis[j], ((i >> j) & 1 ? 1.0 : -1.0) * (hk_v3_get(s->half, j) + extra));
        corner[i] = p;
    }
    for (int i = 0; i < 8; i++)
        for (int j = 0; j < 3; j++) {
            int k = i ^ (1 << j);
            if (k < i) continue;
            double x0, y0, x1, y1;
            to_screen(f, v, corner[i], &x0, &y0);
            to_screen(f, v, corner[k], &x1, &y1);
            hk_canvas_line(c, x0, y0, x1, y1, width, line, 1.0);
        }
}

/* Grid spacing of 1, 2 or 5 times a power of ten giving about eight lines. */
static double grid_step(double range)
{
    double raw = range / 8.0, p = pow(10.0, floor(log10(raw)));
    return raw / p < 2.0 ? p : (raw / p < 5.0 ? 2.0 * p : 5.0 * p);
}

static void draw_grid(hk_Canvas *c, const Frame *f, const View *v)
{
    const double step = grid_step(fmax(f->hi[v->h] - f->lo[v->h], f->hi[v->v] - f->lo[v->v]));
    const hk_Vec3 grey = {0.86, 0.86, 0.86}, axis = {0.7, 0.7, 0.7};
    for (int dir = 0; dir < 2; dir++) {
        int ax = dir == 0 ? v->h : v->v;
        for (double t = ceil(f->lo[ax] / step) * step; t <= f->hi[ax] + 1e-12; t += step) {
            hk_Vec3 a = hk_v3_zero(), b = hk_v3_zero();
            hk_v3_set(&a, ax, t), hk_v3_set(&b, ax, t);
            int other = dir == 0 ? v->v : v->h;
            hk_v3_set(&a, other, f->lo[other]), hk_v3_set(&b, other, f->hi[other]);
            double x0, y0, x1, y1;
            to_screen(f, v, a, &x0, &y0);
            to_screen(f, v, b, &x1, &y1);
            hk_canvas_line(c, x0, y0, x1, y1, 1.0, fabs(t) < 1e-12 ? axis : grey, 1.0);
        }
    }
}

hk_Status hk_plot_strands_png(const char *path, int width, int height, const hk_PlotStrand *strands, int strand_count,
                              const hk_Shape *shapes, int shape_count, double envelope_alpha, hk_Error *err)
{
    hk_Canvas canvas;
    hk_Status st = hk_canvas_alloc(width, height, hk_v3(1, 1, 1), &canvas, err);
    if (st != HK_OK) return st;
    Frame f;
    for (int i = 0; i < 3; i++) f.lo[i] = DBL_MAX, f.hi[i] = -DBL_MAX;
    for (int s = 0; s < strand_count; s++)
        for (int j = 0; j < strands[s].count; j++) grow(&f, strands[s].points[j]);
    for (int s = 0; s < shape_count; s++) {
        hk_Vec3 e = shape_extent(&shapes[s], fmax(0.0, envelope_alpha * shapes[s].volume));
        grow(&f, hk_v3_add(shapes[s].centre, e));
        grow(&f, hk_v3_sub(shapes[s].centre, e));
    }
    if (f.lo[0] > f.hi[0])
        for (int i = 0; i < 3; i++) f.lo[i] = -0.1, f.hi[i] = 0.1;
    f.height = height;
    f.panel_w = width / 2;
    f.margin = 0.06 * fmin(f.panel_w, height);
    const View views[2] = {{2, 1, 0, 0.0}, {0, 1, 2, (double)(width / 2)}};
    double scale = DBL_MAX;
    for (int k = 0; k < 2; k++) {
        double rh = fmax(f.hi[views[k].h] - f.lo[views[k].h], 1e-6);
        double rv = fmax(f.hi[views[k].v] - f.lo[views[k].v], 1e-6);
        scale = fmin(scale, fmin((f.panel_w - 2 * f.margin) / rh, (height - 2 * f.margin) / rv));
    }
    f.scale = scale;
    const hk_Vec3 skin = {0.93, 0.84, 0.76}, outline = {0.55, 0.45, 0.40}, env = {0.80, 0.70, 0.65};
    for (int k = 0; k < 2; k++) {
        const View *v = &views[k];
        draw_grid(&canvas, &f, v);
        for (int s = 0; s < shape_count; s++) {
            const hk_Shape *sh = &shapes[s];
            const double extra = envelope_alpha * sh->volume;
            if (sh->kind == HK_SHAPE_FIELD) continue; /* a mesh: no outline drawn */
            if (sh->kind == HK_SHAPE_CUBOID) {
                if (extra != 0.0) cuboid_outline(&canvas, &f, v, sh, extra, env, 1.0);
                cuboid_outline(&canvas, &f, v, sh, 0.0, outline, 1.5);
            } else {
                if (extra != 0.0) ellipsoid_silhouette(&canvas, &f, v, sh, extra, env, 0.0, env, 1.0);
                ellipsoid_silhouette(&canvas, &f, v, sh, 0.0, skin, 1.0, outline, 1.5);
            }
        }
        for (int s = 0; s < strand_count; s++) {
            const hk_PlotStrand *ps = &strands[s];
            double px = 0, py = 0;
            for (int j = 0; j < ps->count; j++) {
                double x, y;
                to_screen(&f, v, ps->points[j], &x, &y);
                if (j > 0) hk_canvas_line(&canvas, px, py, x, y, 1.6, ps->color, 1.0);
                px = x, py = y;
            }
            if (ps->count > 0) {
                double x, y;
                to_screen(&f, v, ps->points[0], &x, &y);
                hk_canvas_disc(&canvas, x, y, 3.0, hk_v3(0.1, 0.1, 0.1), 1.0); /* the root */
            }
        }
    }
    /* Separator between the two panels. */
    hk_canvas_line(&canvas, width / 2 + 0.5, 0, width / 2 + 0.5, height, 1.0, hk_v3(0.6, 0.6, 0.6), 1.0);
    st = hk_canvas_write_png(&canvas, path, err);
    hk_canvas_free(&canvas);
    return st;
}
