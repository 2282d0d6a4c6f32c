/* The guide-guide contacts of one step solved together over all guides, with
 * Coulomb's static friction (docs/dynamics.md, "Contacts solved together").
 *
 * Per-strand solves with the partners held still (block Jacobi) let touching guides
 * jitter and, with a viscous friction only, slide under their weight: still hair crept
 * by up to 8 mm in 4 s (issue 12). Here every guide's linearly implicit step is opened
 * up (hk_dynamics_euler_delta): its free velocity and its answer to impulses at its
 * contact points (the inverse of the step's matrix seen through the points'
 * Jacobians, the Delassus operator of Moreau and Jean) give the relative velocities at
 * the end of the step as an affine function of the contact impulses. The impulses are
 * found by projected Gauss-Seidel over the contacts (Jean and Moreau 1992; as
 * Daviet, Bertails-Descoubes and Boissieux, "A hybrid iterative solver for robustly
 * capturing Coulomb friction in hair dynamics", SIGGRAPH Asia 2011, do for
 * Super-Helices), with the penalty of hk_hair_contacts as the normal law, implicit over
 * the step:
 *     lambda_n = max(0, h k (d0 - d) - (h^2 k + h c_n) u_n),
 * and Coulomb's law tangentially: the contact sticks (u_t = 0) while |lambda_t| <=
 * mu lambda_n, else slides with |lambda_t| = mu lambda_n (mu = 0: the viscous friction
 * lambda_t = -h c_t u_t of paper 000 §4.1). The impulses then act on every guide as
 * point forces lambda / h held over the step (hk_strand_dynamics_advance), so that a
 * guide whose step is split still gets them. The prediction is each guide's linearly
 * implicit Euler step: hair_sim.c solves TR-BDF2 guides' contacts otherwise (held
 * constant, the impulses of an Euler prediction sent a head of 1 m guides flying). */
#ifndef HK_HAIR_CONTACT_SOLVE_H
#define HK_HAIR_CONTACT_SOLVE_H

#include "hairkit/dynamics.h"
#include "hairkit/hair_contacts.h"

typedef struct hk_ContactSolve hk_ContactSolve;

typedef struct hk_ContactSolveStats {
    int sweeps;       /* Gauss-Seidel sweeps of the last solve */
    int pushing;      /* pairs with a normal impulse */
    int sticking;     /* ... of which stick (within the friction cone's interior) */
    double residual;  /* largest impulse change of the last sweep relative to the largest impulse */
    long evaluations; /* the strands' evaluations in their steps without the contacts (predict) */
} hk_ContactSolveStats;

hk_Status hk_contact_solve_create(int strand_count, hk_ContactSolve **out, hk_Error *err);
void hk_contact_solve_destroy(hk_ContactSolve *cs);

/* The impulses of the pairs found by the last hk_hair_contacts_update (params as given
 * to it) for a step of dt of the strands dyn[0..strand_count) (their state at the
 * step's start; unchanged), the head being in state head_end at the step's end (NULL:
 * still). Each strand's step without the contacts is found first (by the solve
 * itself, or before it by hk_contact_solve_open and hk_contact_solve_predict). */
hk_Status hk_contact_solve(hk_ContactSolve *cs, const hk_HairContacts *contacts, hk_StrandDynamics **dyn,
                           int strand_count, const hk_RigidState *head_end, double dt, hk_ContactSolveStats *stats,
                           hk_Error *err);

/* hk_contact_solve in two: the impulses (hk_contact_solve_sweep), then what the
 * strands take from them (hk_contact_solve_finish: the impulses brought into Coulomb's
 * cone, the strands' velocity changes, the forces), called by every thread of a team
 * (or one thread alone) before any hk_contact_solve_forces or _commit: hair_sim.c
 * finishes in the region of its commits. The next solve starts warm from the last
 * one finished. */
hk_Status hk_contact_solve_sweep(hk_ContactSolve *cs, const hk_HairContacts *contacts, hk_StrandDynamics **dyn,
                                 int strand_count, const hk_RigidState *head_end, double dt,
                                 hk_ContactSolveStats *stats, hk_Error *err);
void hk_contact_solve_finish(hk_ContactSolve *cs);

/* hk_contact_solve_finish strand by strand: once for every strand of the solve, on any
 * thread and in any order, each before its strand's hk_contact_solve_forces or _commit
 * (a strand's share reads the pairs and writes that strand's arrays alone); the same
 * bits. hair_sim.c finishes each guide just before its commit, so that the commits
 * wait for no thread to finish the whole solve first. */
void hk_contact_solve_finish_strand(hk_ContactSolve *cs, int strand);

/* A strand's step without the contacts needs the strand alone, not the pairs: the
 * simulation finds it for every strand while one thread finds the pairs (the contacts'
 * update gained 1.48 times on two threads, the strands' steps 1.92).
 * hk_contact_solve_open sizes the strands' arrays (dyn[0..strand_count), called once,
 * by one thread), then hk_contact_solve_predict once per strand, on any thread and in
 * any order, with the head_end and dt of the hk_contact_solve that follows. */
hk_Status hk_contact_solve_open(hk_ContactSolve *cs, hk_StrandDynamics **dyn, int strand_count, hk_Error *err);
void hk_contact_solve_predict(hk_ContactSolve *cs, hk_StrandDynamics *d, int strand, const hk_RigidState *head_end,
                              double dt);

/* The solve's work before the sweeps, staged by the caller in its own parallel region
 * (hair_sim.c: one region a step for the pairs, the strands' steps and this, instead
 * of four). Once the pairs are found (hk_hair_contacts_update) and the solve opened:
 * hk_contact_solve_layout deals the pairs' points to the strands (one thread; the
 * strands' predictions may go on beside it); then hk_contact_solve_points for every
 * strand, on any threads, once hk_contact_solve_predict has begun on it (it waits for
 * a prediction under way on another thread; of two calls for a strand, the first
 * does the work, the second returns at once); then hk_contact_solve_prepare by every
 * thread of a team (or one thread alone): the pairs' laws, each once its two strands'
 * points are done (waited for, so that a thread needs no barrier between its points
 * and this), the split of the pairs, the points' answers and the warm start, all
 * over by the end of the team's region (or a barrier). The hk_contact_solve that
 * follows (same contacts, dyn, head_end and dt) does whatever of this was not done,
 * with the same bits either way. A failed layout drops the solve under way. */
hk_Status hk_contact_solve_layout(hk_ContactSolve *cs, const hk_HairContacts *contacts, hk_StrandDynamics **dyn,
                                  int strand_count, double dt, hk_Error *err);
void hk_contact_solve_points(hk_ContactSolve *cs, hk_StrandDynamics *d, int strand, const hk_RigidState *head_end);
void hk_contact_solve_prepare(hk_ContactSolve *cs, const hk_HairContacts *contacts, double dt);

/* The result as point forces on strand `strand`, sorted by s (impulse / dt; no
 * linearisation), until the next solve. */
const hk_PointForce *hk_contact_solve_forces(const hk_ContactSolve *cs, int strand, int *count);

/* For a strand with the linearly implicit Euler step that took part in the last solve:
 * ends its step with the velocity the solve found (free velocity plus the impulses'
 * answer, what hk_strand_dynamics_advance would compute with the forces at one step)
 * without evaluating again; a strand without pairs takes its free velocity. Returns 0,
 * the strand unchanged, when it cannot (its matrix does not answer, TR-BDF2, or the
 * step needs splitting): then advance it with the forces.
 * Call at most once per strand and solve. */
int hk_contact_solve_commit(hk_ContactSolve *cs, hk_StrandDynamics *d, int strand, const hk_RigidState *head_end,
                            double dt);

/* Sets whether the full sweeps after a solve's first check the idle pairs from their
 * records (the default) or visit them all as the first does; the same bits either way.
 * Not thread-safe: for the tests that compare the two. */
void hk_contact_solve_idle_records_allow(int allow);

/* Sets whether the sweeps over the pushing pairs visit them from the records the full
 * sweeps before them write (the default) or in place; the same bits either way. Not
 * thread-safe: for the tests that compare the two. */
void hk_contact_solve_push_records_allow(int allow);
#endif
