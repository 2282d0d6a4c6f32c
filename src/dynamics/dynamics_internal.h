/* Private parts of the Super-Helix dynamics (docs/dynamics.md). */
#ifndef HK_DYNAMICS_INTERNAL_H
#define HK_DYNAMICS_INTERNAL_H

#include "hairkit/dynamics.h"

#define HK_GAUSS_MAX      16 /* most Gauss points per element */
#define HK_ANDERSON_DEPTH 4  /* past corrections Newton's iteration mixes (strand_integrator.c) */

/* Gauss-Legendre rules on [0, 1] with 1..HK_GAUSS_MAX points: rule n has its nodes at
 * node[n - 1][0..n) and weights at weight[n - 1][0..n). */
typedef struct hk_GaussTable {
    double node[HK_GAUSS_MAX][HK_GAUSS_MAX];
    double weight[HK_GAUSS_MAX][HK_GAUSS_MAX];
} hk_GaussTable;

/* Fills the table (Newton's iteration on the Legendre polynomials, to rounding). */
void hk_gauss_table_init(hk_GaussTable *table);

/* Kinematic state of a material frame moving along the strand: pose, velocities and
 * the "bias" accelerations, i.e. the accelerations the frame would have if every
 * generalized acceleration q'' were zero (root motion and velocity products only). */
typedef struct hk_FrameKinematics {
    hk_Mat3 frame; /* material frame (columns n0, n1, n2) */
    hk_Vec3 pos;   /* centreline point */
    hk_Vec3 omega; /* world angular velocity of the frame */
    hk_Vec3 vel;   /* world velocity of the point */
    hk_Vec3 alpha; /* bias angular acceleration */
    hk_Vec3 acc;   /* bias acceleration of the point */
} hk_FrameKinematics;

/* A point inside an element, with the Jacobians of its own element's coordinates. */
typedef struct hk_PointKinematics {
    hk_FrameKinematics k;
    hk_Mat3 jac;     /* d pos / d k_P (world), column b per coordinate */
    hk_Mat3 jac_rot; /* d (rotation) / d k_P: world angular velocity per unit k_P' */
} hk_PointKinematics;

/* Kinematics at offset u into element P with start state `start`, coordinates k and
 * rates kd. order 1: pose, velocities, Jacobians; order 2: also bias accelerations. */
void hk_point_kinematics(const hk_FrameKinematics *start, hk_Vec3 k, hk_Vec3 kd, double u, int order,
                         hk_PointKinematics *out);

/* What hk_point_kinematics gives at an element's end that the rates do not change: the
 * end's pose and its Jacobians, for the coordinates and root pose of the walk that
 * reached it. */
typedef struct hk_EndPose {
    hk_Mat3 frame, jac, jac_rot;
    hk_Vec3 pos;
} hk_EndPose;

/* hk_point_kinematics of order 1 at the end of the element that starts at `start`, its
 * pose known, for rates kd: the same bits (the offset R_P d it adds to the start is
 * column 0 of jac_rot = R_P Lambda, the same products), without the element's closed
 * forms. */
void hk_end_kinematics(const hk_FrameKinematics *start, const hk_EndPose *pose, hk_Vec3 kd, hk_PointKinematics *out);

/* hk_point_kinematics of order 2 at the offsets u[0] and u[1] at once (two lanes of
 * vector arithmetic), out[i] for u[i]: the same bits. */
void hk_point_kinematics2(const hk_FrameKinematics *start, hk_Vec3 k, hk_Vec3 kd, const double u[2],
                          hk_PointKinematics out[2]);

/* Pose and velocities alone at offset u (hk_point_kinematics of order 1 without the
 * Jacobians, which cost more than the rest): for points sampled along a strand. */
void hk_point_motion(const hk_FrameKinematics *start, hk_Vec3 k, hk_Vec3 kd, double u, hk_FrameKinematics *out);

/* Position and velocity alone at offset u (hk_point_motion's, the same bits), without
 * the frame and its rates: for points that start nothing beyond them. vel may be NULL. */
void hk_point_velocity(const hk_FrameKinematics *start, hk_Vec3 k, hk_Vec3 kd, double u, hk_Vec3 *pos, hk_Vec3 *vel);

/* hk_point_velocity at the offsets u[0] and u[1] at once (two lanes), pos[i] and vel[i]
 * (vel may be NULL) for u[i]: the same bits. */
void hk_point_velocity2(const hk_FrameKinematics *start, hk_Vec3 k, hk_Vec3 kd, const double u[2], hk_Vec3 pos[2],
                        hk_Vec3 *vel);

/* Position, velocity and the Jacobian d pos / d k_P alone (hk_point_kinematics of
 * order 1's, the same bits), without the frame and the rotation's Jacobian. */
void hk_point_jacobian(const hk_FrameKinematics *start, hk_Vec3 k, hk_Vec3 kd, double u, hk_Vec3 *pos, hk_Vec3 *vel,
                       hk_Mat3 *jac);

/* hk_point_jacobian at the offsets u[0] and u[1] at once (two lanes), entry i for u[i]:
 * the same bits. */
void hk_point_jacobian2(const hk_FrameKinematics *start, hk_Vec3 k, hk_Vec3 kd, const double u[2], hk_Vec3 pos[2],
                        hk_Vec3 vel[2], hk_Mat3 jac[2]);

/* hk_point_kinematics of order 1 at the offsets u[0] and u[1] at once (two lanes), only
 * what a body contact's friction takes: k.pos, k.vel, jac and column 0 of k.frame (the
 * tangent), the same bits; the other fields are left alone. */
void hk_point_contact2(const hk_FrameKinematics *start, hk_Vec3 k, hk_Vec3 kd, const double u[2],
                       hk_PointKinematics out[2]);

/* Per element terms of one step, from its own points (quadrature, contacts). The
 * spatial vectors are (angular; linear) about the world origin: a screw (w; v) moves
 * the point p by w x p + v, a wrench (m; f) is a moment about the origin and a force. */
typedef struct hk_ElementTerms {
    double xi[3][6];       /* screw of the strand beyond the element per unit k_P b */
    double inertia[6][6];  /* effective spatial inertia of the element's own points */
    double coupling[3][6]; /* momentum (dual) of the own points moved by k_P b alone */
    double mass[3][3];     /* effective mass of the own coordinates among themselves */
    double load[3];        /* generalized force of the own points' loads */
    double wrench[6];      /* the own points' loads as one wrench */
} hk_ElementTerms;

/* Adds one point to an element's terms: effective translational mass matrix a and
 * rotational inertia b (may be NULL) at point p with Jacobians jac and jac_rot (NULL
 * with b), load force f and moment tau. */
void hk_element_terms_add(hk_ElementTerms *t, hk_Vec3 p, const hk_Mat3 *a, const hk_Mat3 *b, const hk_Mat3 *jac,
                          const hk_Mat3 *jac_rot, hk_Vec3 f, hk_Vec3 tau);

/* The same for a quadrature point, whose translational mass matrix is a I. */
void hk_element_terms_add_quadrature(hk_ElementTerms *t, hk_Vec3 p, double a, const hk_Mat3 *b, const hk_Mat3 *jac,
                                     const hk_Mat3 *jac_rot, hk_Vec3 f, hk_Vec3 tau);

/* hk_element_terms_add_quadrature for the two points pk[0] and pk[1] (their pos, jac and
 * jac_rot) with a[l], b[l], f[l] and tau[l], in two lanes: the same bits as the two
 * calls, point 0's first. */
void hk_element_terms_add_quadrature2(hk_ElementTerms *t, const hk_PointKinematics pk[2], const double a[2],
                                      const hk_Mat3 b[2], const hk_Vec3 f[2], const hk_Vec3 tau[2]);

/* Fills t->xi from the element's end point (its Jacobians at u = l_P). */
void hk_element_terms_set_screw(hk_ElementTerms *t, const hk_PointKinematics *end);

/* Generalized force of the whole strand: out[3P + b] = load + xi . (wrench beyond). */
void hk_terms_generalized_force(int n, const hk_ElementTerms *terms, double *out);

/* Solves (M + diag(extra)) x = rhs where M is the effective mass the terms describe:
 * dense assembly and Cholesky as A = U U^T, U upper triangular (hk_upper_cholesky; work:
 * HK_DENSE_WORK(n) doubles: the matrix's lower triangle, geo added to it, U with its
 * diagonal's reciprocals and the assembly's scratch) or the O(n) recursion (work:
 * HK_LINEAR_WORK(n) doubles). Returns 0 if the system is not positive definite. */
#define HK_DENSE_WORK(n)  ((size_t)18 * (size_t)(n) * (size_t)(n) + (size_t)3 * (size_t)(n) + HK_ASSEMBLE_WORK(n))
#define HK_LINEAR_WORK(n) ((size_t)21 * (size_t)(n))
/* dense: geo (may be NULL) is a further symmetric 3n x 3n matrix added times scale
 * (its lower triangle read). */
int hk_terms_solve_dense(int n, const hk_ElementTerms *terms, const double *extra, const double *geo, double scale,
                         const double *rhs, double *x, double *work);
int hk_terms_solve_linear(int n, const hk_ElementTerms *terms, const double *extra, const double *rhs, double *x,
                          double *work);

/* Cholesky's factorisation with the unknowns in reverse order: the symmetric a +
 * diag(extra) (n x n, row-major; its lower triangle read) as U U^T with U upper
 * triangular, into u's upper triangle, and U^T into its strict lower part (u may be a),
 * then 1 / U_ii at u + n n (HK_UPPER_FACTOR_SIZE(n) doubles in all): the solves with
 * the factor multiply by them instead of dividing on their chains. U has the same bits
 * as hk_cholesky_factor(n, a reversed, 1.0, extra reversed) read backwards. A point's rows of J are zero beyond its own element, and so are its rows of
 * U^-1 J^T, which the contacts' solve uses (hair_contact_solve.c); the step's own solve
 * takes the same factor, so that a strand's matrix is factored once a step. Returns 0 if
 * the matrix is not numerically positive definite. */
int hk_upper_cholesky(int n, const double *a, const double *extra, double *u);
#define HK_UPPER_FACTOR_SIZE(n) ((size_t)(n) * (size_t)(n) + (size_t)(n))

/* Solves U U^T x = b in place (x holds b on entry) with hk_upper_cholesky's factor. */
void hk_upper_solve(int n, const double *u, double *x);

/* Solves U^T x = y in place (x holds y on entry), U upper triangular (n x n, row-major):
 * hk_upper_solve's second half, with hk_upper_cholesky's factor (U, then 1 / U_ii). Each
 * x_i takes its terms U_ki x_k in the order of k, then the product by 1 / U_ii: the bits
 * of that sum taken along U's column i. */
void hk_upper_transpose_solve(int n, const double *u, double *x);

/* out = (M + diag(extra)) x in O(n) (two sweeps; screws: 6 n doubles of work). */
void hk_terms_multiply(int n, const hk_ElementTerms *terms, const double *extra, const double *x, double *out,
                       double *screws);

/* Dense effective mass matrix (9 n^2 values, row-major) of the terms; scratch holds
 * HK_ASSEMBLE_WORK(n) doubles. */
#define HK_ASSEMBLE_WORK(n) ((size_t)18 * (size_t)(n))
void hk_terms_assemble(int n, const hk_ElementTerms *terms, double *mass, double *scratch);

/* Body contact of one sample (paper 000 §4.2) at world position pos moving at vel, the
 * hair's tangent there, the head in state head: the penalty force of the shapes (head
 * space) with anisotropic friction, as a point force with its linearisation. Returns 0
 * when the point touches no shape. */
typedef struct hk_BodyContact {
    const hk_Shape *shapes;
    int shape_count;
    double envelope_alpha;
    double weight; /* arc length the sample stands for (m) */
    double friction_with, friction_against, friction_velocity;
} hk_BodyContact;

int hk_body_contact_force(const hk_BodyContact *bc, const hk_RigidState *head, hk_Vec3 pos, hk_Vec3 vel,
                          hk_Vec3 tangent, hk_PointForce *out);

/* The friction alone, for a sample whose penalty energy has the world gradient grad
 * (hk_strand_workspace_contact, turned to world axes): the normal force, -grad, then
 * comes from the gradient of the potential. Returns 0 when grad is zero. */
int hk_body_contact_friction(const hk_BodyContact *bc, const hk_RigidState *head, hk_Vec3 pos, hk_Vec3 vel,
                             hk_Vec3 tangent, hk_Vec3 grad, hk_PointForce *out);

/* The state of one strand's dynamics (hairkit/dynamics.h). The vectors are 3N values
 * each, one block. */
struct hk_StrandDynamics {
    hk_SuperHelix *sh;
    hk_DynamicsDef params;
    hk_Vec3 root_head;  /* root in head space */
    hk_Mat3 frame_head; /* root frame in head space */
    hk_Shape *shapes;   /* body shapes (head space), owned copy */
    hk_BodyContact contact;
    hk_BodyContact tip; /* the tip's penalty: the body shapes alone (tip_shapes), no
                           envelope, weight CollisionStep / 2 (tip_contact.c) */
    hk_Shape *tip_shapes;
    int contact_samples;           /* collision samples along the strand (0: no body) */
    int contact_count;             /* samples in contact during the last evaluation */
    hk_StrandEnvDef potential_env; /* no shapes: elastic + gravity */
    hk_StrandWorkspace *ws;
    double *v;      /* generalized velocity q' */
    double *delta;  /* Newton correction of the velocity */
    double *rhs;    /* generalized force (evaluate), then the residual */
    double *extra;  /* diagonal of the iteration matrix beyond M: ch gamma l + ch^2 K l */
    double *grad;   /* gradient of the potential at q */
    double *saved;  /* q and v before a step that may be undone, 2 x 3N */
    double *start;  /* q and v at the start of hk_strand_dynamics_advance, 2 x 3N */
    double *acc;    /* q'' at the end of the last step (TR-BDF2 "first same as last") */
    double *acc_at; /* q and v (2 x 3N) for which acc holds: a velocity set by the
                       caller makes it stale */
    int acc_valid;
    double energy; /* hk_dynamics_total_energy for the state of acc_at (energy_valid) */
    int energy_valid;
    double *q0, *v0;           /* the step's start */
    double *aq, *av;           /* the known parts of a stage, q = aq + ch v, v = av + ch q'' */
    double *x;                 /* v - av */
    double *vg, *qg;           /* the first stage's result */
    double *prev_v0, *prev_vg; /* the last step's start and first-stage velocities, and its
                                  step prev_h: Newton's first guesses are extrapolated from them */
    double prev_h;
    double *start_guess; /* a stage's first guess, for its dense fallback */
    double *mixing;      /* Anderson's history in Newton's iteration (strand_integrator.c):
                            2 x HK_ANDERSON_DEPTH differences and the last iterate and
                            correction, 3N each */
    int prev_at_end;     /* the step starts where the last one ended */
    double *work;
    /* where the caller's point forces act at the start of the step (or of the
     * interval of hk_strand_dynamics_advance): within it they follow their
     * linearisation F0 - K (x - x0) - D (v - v0) */
    hk_Vec3 *anchor_pos, *anchor_vel;
    int anchor_capacity;
    /* HK_STIFFNESS_FULL: the potential with the body's penalty; its Hessian, then G+
     * (the positive part of the geometric stiffness, kept between refreshes); the
     * work of G+'s computation (HK_POSITIVE_PART_WORK(3N), the Cholesky factor first) */
    hk_StrandEnvDef body_env;
    hk_StrandWorkspace *ws_body;
    double *hess, *hess_pos, *geo_work;
    int hess_pos_valid;
    int geo_indefinite; /* the last G decomposed had a negative eigenvalue (positive_part) */
    /* The O(N) solver's stage that does not converge is solved again with the dense
     * matrix and the potential's Hessian (dense_fallback set for it); dense_work, hess
     * and its companions are then allocated on first use. */
    int dense_fallback;
    double *dense_work;
    /* contact_entry.c: the collision samples' arc lengths and the tip's (entry_count),
     * and their head-space positions for the coordinates of two recent states (a
     * step's end is the next one's start): slot k holds entry_q[k] (3N),
     * entry_pos[k] (entry_count; computed where entry_known[k], hk_dynamics_potential_walk)
     * and the nodes of the same walk entry_nodes[k] (N + 1, for the step's largest
     * travel), valid when entry_valid[k] */
    double *entry_s, *entry_q[2];
    hk_Vec3 *entry_pos[2], *entry_nodes[2];
    unsigned char *entry_known[2];
    int entry_count, entry_valid[2], entry_next;
    /* The element ends' poses of the last sweep (strand_dynamics.c), which the contact
     * points' Jacobians at the same state walk to again (strand_response.c): they hold
     * for the coordinates ends_q (3N) and the root pose ends_root, ends_frame, which
     * hk_dynamics_end_poses compares with the strand's (whatever changed q or placed
     * the root makes them stale; the elements' lengths are fixed at creation). */
    hk_EndPose *ends;
    double *ends_q;
    hk_Vec3 ends_root;
    hk_Mat3 ends_frame;
    int ends_valid;
    long evaluations; /* evaluations of the forces, to refresh G+ every few */
    hk_DynamicsStats stats;
    hk_ElementTerms *terms;
    hk_GaussTable gauss;
};

/* Evaluates the equations of motion at the strand's q (sh->q) and velocity d->v with
 * the head in state head (its root placed there): d->terms hold the iteration matrix's
 * mass part M + ch D_points + ch^2 K_points (and air drag), d->extra its diagonal
 * (internal friction and elastic stiffness), d->rhs the generalized force f(q, v) minus
 * M x / ch when x is given (the stage's inertia, so that ch rhs is the stage's
 * residual). ch = 0 (x NULL): the plain mass matrix and f. */
void hk_dynamics_evaluate(hk_StrandDynamics *d, const hk_RigidState *head, const hk_PointForce *forces, int force_count,
                          double ch, const double *x);

/* The element ends' poses (N) of the last sweep when they hold for the strand's
 * coordinates and root pose now, else NULL. */
const hk_EndPose *hk_dynamics_end_poses(const hk_StrandDynamics *d);

/* Solves (iteration matrix) out = d->rhs after hk_dynamics_evaluate with the same ch;
 * returns 0 if the system is not positive definite. */
int hk_dynamics_solve(hk_StrandDynamics *d, double ch, double *out);

/* The strand's nodes (N + 1) or tip for coordinates q, in head space (where the body's
 * shapes are). */
void hk_dynamics_head_space_nodes(hk_StrandDynamics *d, const double *q, hk_Vec3 *nodes);
hk_Vec3 hk_dynamics_head_space_tip(hk_StrandDynamics *d, const double *q);

/* HK_STIFFNESS_FULL (with the linearly implicit Euler step, contact_entry.c): the walk
 * of the potential with the body's penalty (its nodes and
 * collision samples, head space) for coordinates q, kept for the next evaluation when
 * it is at q (hk_strand_workspace_prepare): the collision samples' positions (points,
 * contact_samples, known[i] where computed: not for elements beyond every shape's
 * reach), the tip's (points[contact_samples], the last node) and the nodes (N + 1). */
void hk_dynamics_potential_walk(hk_StrandDynamics *d, const double *q, hk_Vec3 *points, unsigned char *known,
                                hk_Vec3 *nodes);

/* The strand's points at the arc lengths s[0..count) (ascending) for coordinates q, in
 * head space, and its nodes (N + 1; may be NULL) from the same walk. */
void hk_dynamics_head_space_walk(hk_StrandDynamics *d, const double *q, const double *s, int count, hk_Vec3 *points,
                                 hk_Vec3 *nodes);

/* The tip's body contact (tip_contact.c), the tip's kinematics given: fills pf and
 * returns 1 when the tip is inside a body shape. */
int hk_dynamics_tip_contact(const hk_StrandDynamics *d, const hk_RigidState *head, const hk_PointKinematics *tip,
                            hk_PointForce *pf);

/* The tip penalty's energy at coordinates q (head space). */
double hk_dynamics_tip_energy(hk_StrandDynamics *d, const double *q);

/* Deepest that a collision sample or the tip ends inside a body shape (not a styling
 * one) over a step from the coordinates `before` to `after`, among the shapes whose
 * penalty (the sample's with the strand's envelope, the tip's without) it did not feel
 * before: what the linearly implicit Euler step, which sees the contacts of its start,
 * lets in unopposed (contact_entry.c). 0 when none. */
double hk_dynamics_largest_entry(hk_StrandDynamics *d, const double *before, const double *after);

/* The strand's head-space nodes (N + 1) for coordinates q, from the cache of
 * hk_dynamics_largest_entry (filled for q when absent): the same bits as
 * hk_dynamics_head_space_nodes, but the potential's (hk_dynamics_potential_walk) with
 * the full stiffness and the linearly implicit Euler step. Only with collision samples
 * (contact_samples > 0). */
const hk_Vec3 *hk_dynamics_entry_nodes(hk_StrandDynamics *d, const double *q);

/* Kinetic plus potential energy with the body's penalty (the energy that the motion
 * conserves on a still head without friction); *kinetic (may be NULL) its kinetic part. */
double hk_dynamics_total_energy(hk_StrandDynamics *d, const hk_RigidState *head, double *kinetic);

/* Allocates what the dense fallback of the O(N) solver needs; 0 when out of memory. */
int hk_dynamics_dense_ready(hk_StrandDynamics *d);

/* G+, the positive part of the geometric stiffness of the last refresh (full
 * stiffness only). */
const double *hk_dynamics_geometric_positive(hk_StrandDynamics *d);

/* Positions and velocities of the caller's point forces now (the anchors). */
hk_Status hk_dynamics_anchor_forces(hk_StrandDynamics *d, const hk_RigidState *head, const hk_PointForce *forces,
                                    int force_count, hk_Error *err);

/* The linearly implicit Euler step's velocity change (paper 000 §3.4; strand_integrator.c)
 *     (M + h D + h^2 K) dv = h (f - h K v)
 * into d->delta, the state unchanged; d->terms and d->extra keep the matrix for
 * hk_dynamics_resolve. Returns 0 if the matrix is not positive definite or dv not
 * finite. */
int hk_dynamics_euler_delta(hk_StrandDynamics *d, const hk_RigidState *head, const hk_PointForce *forces,
                            int force_count, double h);

/* Ends a linearly implicit Euler step of h with the new velocity v (3N): q += h v, the
 * root placed with the head's state at the step's end. Returns 0, the state unchanged,
 * when the step would not be accepted by hk_strand_dynamics_advance (a frame turning
 * more than max_turn, a node near the body travelling more than max_travel, or not
 * finite): the caller then advances with error control. */
int hk_dynamics_euler_commit(hk_StrandDynamics *d, const double *v, double h, const hk_RigidState *head_end);

/* Solves the matrix of the last hk_dynamics_euler_delta for rhs into out (both 3N; may
 * alias), reusing the dense solver's Cholesky factor. Returns 0 if it cannot. */
int hk_dynamics_resolve(hk_StrandDynamics *d, const double *rhs, double *out);

/* The root's kinematics with the head in state head: a point of the head, its frame
 * turning with it (the strand's root must be placed with that state). */
hk_FrameKinematics hk_dynamics_root_kinematics(const hk_StrandDynamics *d, const hk_RigidState *head);

/* hk_dynamics_resolve for `count` right-hand sides, the rows of rhs (count x 3N), into
 * the rows of out, one by one (the contacts' solve takes the dense solver's strands by
 * their reversed factor, hk_dynamics_reversed_factor: this is for the O(N) solver and
 * the dense fallback). Returns 0 if it cannot. */
int hk_dynamics_resolve_rows(hk_StrandDynamics *d, const double *rhs, int count, double *out);

/* The matrix A of the last successful hk_dynamics_euler_delta as A = U U^T with U
 * upper triangular (3N x 3N, row-major): the factor its dense solve took
 * (hk_upper_cholesky), with U^T in its strict lower part as hk_upper_cholesky writes it
 * (row i there holds column i of U, contiguous for the contacts' back substitutions,
 * hair_contact_solve.c), then the 3N reciprocals 1 / U_ii. Read in place, not copied:
 * valid until the strand's next dense solve. NULL without a dense matrix (the O(N) solver or its dense fallback). */
const double *hk_dynamics_reversed_factor(const hk_StrandDynamics *d);

/* Jacobians of `count` points at the sorted arc lengths s for the current q: jac holds
 * count blocks of 3 x 3N (row-major: d pos / d q'), or with packed of 3 x 3(p + 1) for
 * a point on element p (its columns up to its element's, beyond which its rows are
 * zero), each block right after the last; pos and vel (may be NULL) the world
 * positions and the velocities with the generalized velocities `rates` and the head's
 * state head (the root's motion), element (may be NULL) the element each lies on.
 * screws: 18 N doubles of work (the screws of the elements' ends, component by component). */
void hk_dynamics_point_jacobians(hk_StrandDynamics *d, const hk_RigidState *head, const double *rates, const double *s,
                                 int count, double *screws, double *jac, int packed, hk_Vec3 *pos, hk_Vec3 *vel,
                                 int *element);

/* The generalized mass matrix M(q) (3N x 3N, row-major), assembled densely, for tests
 * and diagnostics. */
hk_Status hk_strand_dynamics_mass_matrix(hk_StrandDynamics *d, double *mass, hk_Error *err);

#endif
