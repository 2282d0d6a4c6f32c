/* The piecewise fitter's parts (curvefit.h; docs/helicoid-fitting.md): one piece
 * (fit_piece.c), cuts and the recursion (fit_cuts.c), fixed layouts and the polish of a
 * chain (fit_chain.c), options and entry points (piecewise_fit.c). Private. */
#ifndef HK_PIECEWISE_INTERNAL_H
#define HK_PIECEWISE_INTERNAL_H

#include "optimize/curvefit_internal.h"

#define MAXP HK_CURVEFIT_MAX_PARAMS
#define ROT  3 /* parameters of the root frame's rotation when it is refined */
/* Least-squares residuals of a fragment of m samples: 3 per sample and one per model
 * parameter (the regularisation). */
#define RESIDUALS(m) (3 * (size_t)(m) + MAXP + 3)
/* The polish of a whole chain (least squares): all pieces' parameters at once, up to the
 * minimiser's limit; 3 residuals per sample and one per parameter. */
#define POLISH_PARAMS      HK_LEAST_SQUARES_MAX_PARAMS
#define CHAIN_RESIDUALS(n) (3 * (size_t)(n) + POLISH_PARAMS)

/* Plain traces remembered by hk_cf_trace (fit_piece.c). The fits trace the same
 * arguments again and again: the candidates' costs then the Levenberg-Marquardt run from
 * the best of them, the run's last step then its cost and the piece made of it
 * (docs/helicoid-fitting.md §7: on Curly's strands of 16-32 points 17 % of the traced
 * points repeat one of the last 8 traces, 19 % one of the last 64). */
#define TRACE_CACHE 8

typedef struct TraceEntry {
    hk_CurveModelFn model; /* NULL: empty */
    double params[MAXP];
    hk_CurveStart start;
    int m;
    int status; /* hk_cf_trace's result */
    hk_CurveStart end;
} TraceEntry;

/* The polish's last chain traced with parameters that are not a Jacobian column's (see
 * trace_params, fit_chain.c): its parameters, each piece's start and end pose; its points
 * in hk_CurveFitWorkspace.ref_points. pieces = 0: empty. */
typedef struct ChainRef {
    int pieces;
    double x[POLISH_PARAMS];
    hk_CurveStart start[HK_CURVEFIT_MAX_PIECES], end[HK_CURVEFIT_MAX_PIECES];
} ChainRef;

struct hk_CurveFitWorkspace {
    int capacity;
    hk_Vec3 *target; /* the resampled target */
    hk_Vec3 *trace;  /* the objective's model output */
    hk_Vec3 *best;   /* a fit's trace kept for the split heuristics */
    hk_Vec3 *chain;  /* chained pieces, for the error of a split and of the result */
    double *row;     /* 2 * capacity: dynamic programming rows */
    double *prefix;  /* coupling of growing fragments */
    double *diff;    /* bend differences */
    double *lsq;     /* Levenberg-Marquardt work memory */
    hk_Vec3 *dtrace; /* MAXP * capacity: the trace's derivatives (model_derivative) */
    /* the last TRACE_CACHE traces (emptied by each fit), their points TRACE_CACHE *
     * capacity; `next` the entry replaced next */
    TraceEntry cache[TRACE_CACHE];
    hk_Vec3 *cache_points;
    int next;
    ChainRef ref;
    hk_Vec3 *ref_points; /* capacity */
};

typedef struct Piece {
    double params[MAXP];
    double rot[ROT];     /* rotation of the root frame (refined first piece), else 0 */
    hk_CurveStart start; /* the pose it starts from */
    hk_CurveStart base;  /* at the root: that pose before the model's root_frame rule */
    hk_CurveStart end;   /* and ends at */
    double error;        /* normalised coupling against its fragment (m) */
    double frechet;      /* Fréchet distance against its fragment (m) */
    double join_error;   /* least squares, a piece with a successor: how far its end
                            tangent's error turns the rest (m), see residuals() */
} Piece;

typedef struct Fit {
    hk_CurveFitWorkspace *ws;
    hk_CurveModelFn model;
    hk_CurveModelDerivFn derivative; /* of model (NULL: differences) */
    void *user;
    int np;
    const double *seed;
    double scale[MAXP + ROT];
    const hk_CurveFitDef *opt;
    int n;          /* samples */
    double h;       /* their spacing */
    int min_points; /* samples of the shortest fragment a split may create */
    long evaluations;
    hk_CurveFit *out;
    hk_CurveStart starts[HK_CURVEFIT_MAX_PIECES]; /* start pose of each emitted piece */
    hk_CurveStart root_base;                      /* the root piece's pose before root_frame */
    hk_Error *err;
    /* what the objective compares: samples i0 .. i0 + m - 1, traced from `base`, turned
     * by the last ROT parameters when `rotating` */
    int i0, m, rotating;
    hk_CurveStart base;
    /* 1 while the cut search probes a fragment: one Levenberg-Marquardt run, from the best
     * start (the last fragment that fitted), instead of up to MAX_STARTS (fit_cuts.c) */
    int single_start;
    /* 1 while hk_cf_finish_pieces refits a piece from its parameters (the first hint):
     * one run from them, at the root with the frame's rotation free from the start */
    int finishing;
    /* 1 when ws->chain holds the output's chain as measure() traces it (hk_cf_finish_pieces
     * kept the chain it last traced) */
    int chain_traced;
} Fit;

/* Traces m samples of the model from `start` into out, counting the evaluation; 0 when
 * the model succeeded with finite points and end pose. */
int hk_cf_trace(Fit *F, const double *params, const hk_CurveStart *start, int m, hk_Vec3 *out, hk_CurveStart *end);

/* The weight of parameter j in the regularisation (options.penalty_weight, 0 = 1). */
double hk_cf_penalty_weight(const hk_CurveFitDef *o, int j);

/* Least-squares rows: the 3 m distances of model and target points, weighted 1/sqrt(m)
 * (half the mean squared distance as cost), and the regularisation lambda w_j x_j of
 * `count` parameters (weights cycling with the model's parameter count). */
void hk_cf_distance_residuals(const hk_Vec3 *model, const hk_Vec3 *target, int m, double *r);
void hk_cf_penalty_residuals(const Fit *F, const double *x, int count, double *r);

/* The Levenberg-Marquardt settings of the fits for nx parameters. */
hk_LeastSquaresDef hk_cf_least_squares_options(const Fit *F, int nx);

/* Fits samples i0..i1 from `start` (see fit_piece.c), from the seeds and hints. */
hk_Status hk_cf_fit_piece(Fit *F, int i0, int i1, const hk_CurveStart *start, int may_refine, const Piece *hint1,
                          const Piece *hint2, Piece *piece);

/* 1 when a piece follows its fragment within the tolerance and, with a successor, leaves
 * it a start tangent that turns the rest by no more. */
int hk_cf_acceptable(const Fit *F, const Piece *p);

/* Appends the piece (samples i0..i1) to the output. */
void hk_cf_emit(Fit *F, const Piece *p, int i0, int i1);

/* Traces pieces [from, to) of `fit` chained from `start` into out (indexed by sample; the
 * last piece ends at sample i_end). 0 on success. */
int hk_cf_trace_chain(hk_CurveModelFn model, void *user, const hk_CurveFit *fit, int from, int to, int i_end, double h,
                      const hk_CurveStart *start, hk_Vec3 *out, long *evaluations);

/* Fits samples i0..i1 from `start` with at most `budget` pieces, recursively (§5.3). */
hk_Status hk_cf_fit_range(Fit *F, int i0, int i1, const hk_CurveStart *start, int budget, const Piece *known,
                          const Piece *hint, hk_CurveStart *end);

/* A fixed layout (§5.4): piece k spans samples bounds[k]..bounds[k + 1], k < pieces. */
hk_Status hk_cf_fit_fixed(Fit *F, const int *bounds, int pieces, const hk_CurveStart *start);

/* With options.final_model: the output's pieces fitted again with it (see curvefit.h);
 * F->model is that model on return. */
hk_Status hk_cf_finish_pieces(Fit *F);

/* Refits all the output's pieces together (least squares); keeps the result, with the
 * output's start and errors, only when its coupling is lower. */
hk_Status hk_cf_polish_chain(Fit *F);

#endif
