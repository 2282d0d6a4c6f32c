/* Dissipative penalty forces between guide strands (paper 000 §4.1: "contacts
 * between hair volumes are handled by dissipative penalty forces" as in Choe et al.
 * 2005, "a normal elastic response together with a tangential viscous friction").
 *
 * For a pair closer than d0, with n the unit normal from the closest point b to a,
 * d = |a - b| and w = v_a - v_b the relative velocity of the closest points:
 *     f_n = k (d0 - d) - c_n (w . n)          (Kelvin-Voigt on the overlap)
 *     F_a = max(f_n, 0) n - c_t (w - (w . n) n),     F_b = -F_a.
 * The damping acts both ways (approach and separation), so that a resting contact
 * is a linear spring-damper whose linearisation is exact for the implicit step; the
 * clamp at zero keeps the contact from ever pulling (no sticking). The clamped force
 * is still dissipative: it only removes the part -k (d0 - d) of a damping force that
 * opposes a separating w. Forces are equal and opposite, so momentum is conserved. */
#include <stdlib.h>
#include <string.h>

#include "hair_contacts_internal.h"

static hk_Vec3 lerp(hk_Vec3 a, hk_Vec3 b, double t) { return hk_v3_madd(a, hk_v3_sub(b, a), t); }

static hk_Vec3 velocity_at(const hk_HcStrand *st, int k, double t)
{
    return st->vel ? lerp(st->vel[k], st->vel[k + 1], t) : hk_v3_zero();
}

/* A unit vector normal to both segments when their closest points coincide (d = 0:
 * the centrelines cross exactly), or normal to one of them when they are parallel;
 * always the same for the same input. */
static hk_Vec3 fallback_normal(hk_Vec3 d1, hk_Vec3 d2)
{
    hk_Vec3 n = hk_v3_cross(d1, d2);
    if (hk_v3_norm2(n) > 0.0) return hk_v3_normalize(n);
    hk_Vec3 d = hk_v3_norm2(d1) > 0.0 ? d1 : d2;
    if (hk_v3_norm2(d) == 0.0) return hk_v3(0.0, 1.0, 0.0);
    /* Cross with the axis the direction leans on least. */
    const double ax = fabs(d.x), ay = fabs(d.y), az = fabs(d.z);
    hk_Vec3 axis = ax <= ay && ax <= az ? hk_v3_unit(0) : (ay <= az ? hk_v3_unit(1) : hk_v3_unit(2));
    return hk_v3_normalize(hk_v3_cross(d, axis));
}

static void pair_contact(const hk_HairContacts *c, const hk_HcPair *p, hk_HcContact *out)
{
    const hk_HcStrand *si = &c->views[p->i], *sj = &c->views[p->j];
    const hk_HairContactDef *pr = &c->p;
    memset(out, 0, sizeof *out);
    out->force_index[0] = out->force_index[1] = -1;
    out->point[0] = lerp(si->pos[p->a], si->pos[p->a + 1], p->u);
    out->point[1] = lerp(sj->pos[p->b], sj->pos[p->b + 1], p->v);
    out->s[0] = si->s[p->a] + p->u * (si->s[p->a + 1] - si->s[p->a]);
    out->s[1] = sj->s[p->b] + p->v * (sj->s[p->b + 1] - sj->s[p->b]);
    /* Distance and normal from the closest points themselves, so that what is
     * reported is what the force is computed from. */
    hk_Vec3 n = hk_v3_sub(out->point[0], out->point[1]);
    const double d = hk_v3_norm(n);
    out->distance = d;
    n = d > 1e-9 * pr->distance
            ? hk_v3_scale(n, 1.0 / d)
            : fallback_normal(hk_v3_sub(si->pos[p->a + 1], si->pos[p->a]), hk_v3_sub(sj->pos[p->b + 1], sj->pos[p->b]));
    out->normal = n;
    if (!(d < pr->distance)) return;
    out->active = 1;
    if (c->geometry_only) return;
    const hk_Vec3 w = hk_v3_sub(velocity_at(si, p->a, p->u), velocity_at(sj, p->b, p->v));
    const double wn = hk_v3_dot(w, n);
    const double fn = pr->stiffness * (pr->distance - d) - pr->damping * wn;
    const hk_Mat3 nn = hk_m3_outer(n, n);
    const hk_Mat3 id = hk_m3_identity();
    hk_Mat3 tangential = hk_m3_scale(&nn, -1.0);
    tangential = hk_m3_add(&id, &tangential);
    /* Tangential viscous friction on the sliding velocity w - (w . n) n. */
    out->force = hk_v3_scale(hk_v3_madd(w, n, -wn), -pr->friction);
    out->damping = hk_m3_scale(&tangential, pr->friction);
    out->stiffness = hk_m3_zero();
    if (fn > 0.0) {
        out->force = hk_v3_madd(out->force, n, fn);
        out->stiffness = hk_m3_scale(&nn, pr->stiffness);
        hk_Mat3 normal_damping = hk_m3_scale(&nn, pr->damping);
        out->damping = hk_m3_add(&out->damping, &normal_damping);
    }
}

/* Order of a strand's forces: by s, then by record index (pair order, point 0
 * before point 1), a total order so that any sort gives the same result. */
typedef struct ForceKey {
    double s;
    int record;
} ForceKey;

static int force_key_cmp(const void *x, const void *y)
{
    const ForceKey *a = x, *b = y;
    if (a->s != b->s) return a->s < b->s ? -1 : 1;
    return (a->record > b->record) - (a->record < b->record);
}

hk_Status hk_hc_forces(hk_HairContacts *c, hk_Error *err)
{
    const int n = c->pair_count, g = c->strand_count;
    if (n > c->contact_cap) {
        hk_HcContact *grown = hk_alloc_array((size_t)n, sizeof *grown, err);
        if (!grown) return HK_ERR_NOMEM;
        hk_free(c->contacts);
        c->contacts = grown;
        c->contact_cap = n;
    }
#pragma omp parallel for schedule(static) num_threads(hk_hc_threads(c))
    for (int k = 0; k < n; k++) pair_contact(c, &c->pairs[k], &c->contacts[k]);
    c->contact_count = 0;
    memset(c->force_start, 0, (size_t)(g + 1) * sizeof *c->force_start);
    for (int k = 0; k < n; k++)
        if (c->contacts[k].active) {
            c->contact_count++;
            c->force_start[c->pairs[k].i + 1]++;
            c->force_start[c->pairs[k].j + 1]++;
        }
    if (c->geometry_only) {
        memset(c->force_start, 0, (size_t)(g + 1) * sizeof *c->force_start);
        return HK_OK;
    }
    for (int s = 0; s < g; s++) c->force_start[s + 1] += c->force_start[s];
    const int total = c->force_start[g];
    if (total > c->force_cap || total > c->force_key_cap) {
        hk_free(c->forces), hk_free(c->force_key);
        c->forces = hk_alloc_array((size_t)total, sizeof *c->forces, err);
        c->force_key = hk_alloc_array((size_t)total, sizeof(ForceKey), err);
        c->force_cap = c->force_key_cap = (c->forces && c->force_key) ? total : 0;
        if (!c->force_cap && total > 0) {
            memset(c->force_start, 0, (size_t)(g + 1) * sizeof *c->force_start);
            return HK_ERR_NOMEM;
        }
    }
    /* Deal the records to the strands in pair order, then sort each strand's list. */
    ForceKey *keys = (ForceKey *)c->force_key;
    hk_PointForce *forces = c->forces;
    int *fill = c->force_order;
    memcpy(fill, c->force_start, (size_t)g * sizeof *fill);
    for (int k = 0; k < n; k++) {
        const hk_HcContact *ct = &c->contacts[k];
        if (!ct->active) continue;
        const int strand[2] = {c->pairs[k].i, c->pairs[k].j};
        for (int side = 0; side < 2; side++) {
            const int slot = fill[strand[side]]++;
            keys[slot].s = ct->s[side];
            keys[slot].record = 2 * k + side;
        }
    }
#pragma omp parallel for schedule(dynamic, 16) num_threads(hk_hc_threads(c))
    for (int s = 0; s < g; s++) {
        const int begin = c->force_start[s], count = c->force_start[s + 1] - begin;
        if (count > 1) qsort(keys + begin, (size_t)count, sizeof *keys, force_key_cmp);
        for (int x = begin; x < begin + count; x++) {
            hk_HcContact *ct = &c->contacts[keys[x].record / 2];
            const int side = keys[x].record % 2;
            hk_PointForce *f = &forces[x];
            ct->force_index[side] = x - begin;
            f->s = ct->s[side];
            f->force = side == 0 ? ct->force : hk_v3_neg(ct->force);
            f->stiffness = ct->stiffness;
            f->damping = ct->damping;
        }
    }
    return HK_OK;
}
