/*
 * lookup.h — C ABI of the `lookup` crate: evaluation of homogenized thermal
 * contact laws written by tcgen (file format: schemas/law.md).
 *
 * Units: SI (Pa, W/m^2, K, W/(m^2 K)). The flux is the magnitude |h| of the
 * heat flowing from body 1 (slave, upper) to body 2 (master, lower); the jump
 * theta_1 - theta_c >= 0 (Temizer 2014, Eq. (2.6)); the conductance is
 * k = |h| / jump (Eq. (2.7)).
 *
 * Conventions: every function returning int32_t returns a status code
 * (LOOKUP_OK = 0 on success); on failure lookup_last_error() gives a message
 * for the calling thread. No function aborts or unwinds into the caller.
 * Evaluations may run concurrently on one handle; lookup_law_set_* and
 * lookup_law_free must not overlap with other calls on the same handle.
 *
 * Link: liblookup.a (static; on Linux also -lpthread -ldl -lm) or liblookup.so.
 */
#ifndef LOOKUP_H
#define LOOKUP_H

#include <stddef.h>
#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

/* Status codes. */
#define LOOKUP_OK 0
#define LOOKUP_ERR_NULL_ARGUMENT 1      /* a required pointer is NULL */
#define LOOKUP_ERR_IO 2                 /* file could not be read or written */
#define LOOKUP_ERR_FORMAT 3             /* not a valid law file */
#define LOOKUP_ERR_VERSION 4            /* unsupported format version */
#define LOOKUP_ERR_CHECKSUM 5           /* corrupted file (CRC-32 mismatch) */
#define LOOKUP_ERR_INVALID_ARGUMENT 6   /* invalid grid data, axis/policy code, cap */
#define LOOKUP_ERR_NON_FINITE 7         /* NaN or infinite query */
#define LOOKUP_ERR_INVALID_QUERY 8      /* p < 0, h < 0, theta <= 0, jump < 0 */
#define LOOKUP_ERR_OUT_OF_RANGE 9       /* outside the table, policy 'error' */
#define LOOKUP_ERR_VANISHING_JUMP 10    /* jump <= 0 and no conductance cap */
#define LOOKUP_ERR_NON_FINITE_RESULT 11 /* overflow (extreme extrapolation) */
#define LOOKUP_ERR_PANIC 12             /* internal error (a bug) */
#define LOOKUP_ERR_MATERIAL_MISMATCH 13 /* material differs from the law's (or none recorded) */

/* Axis codes. */
#define LOOKUP_AXIS_ALL (-1)
#define LOOKUP_AXIS_PRESSURE 0
#define LOOKUP_AXIS_FLUX 1
#define LOOKUP_AXIS_CONTACT_TEMPERATURE 2

/* Extrapolation policy codes. */
#define LOOKUP_EXTRAPOLATE_ERROR 0  /* out of range is an error */
#define LOOKUP_EXTRAPOLATE_CLAMP 1  /* the law is constant beyond the table */
#define LOOKUP_EXTRAPOLATE_LINEAR 2 /* linear in (ln p, h, theta) beyond it */
#define LOOKUP_EXTRAPOLATE_POWER 3  /* pressure only: jump ~ p^s from the end cell */

/* Bits of the `flags` fields. */
#define LOOKUP_FLAG_EXTRAPOLATED_PRESSURE 1u
#define LOOKUP_FLAG_EXTRAPOLATED_FLUX 2u
#define LOOKUP_FLAG_EXTRAPOLATED_CONTACT_TEMPERATURE 4u
#define LOOKUP_FLAG_CONDUCTANCE_CAPPED 8u
#define LOOKUP_FLAG_NO_ERROR_ESTIMATE 16u /* the law has no discretization-error estimate */

/* Body codes of lookup_law_check_material. */
#define LOOKUP_BODY_UPPER 1 /* body 1, slave */
#define LOOKUP_BODY_LOWER 2 /* body 2, master */

/* Opaque handle of a law. */
typedef struct lookup_law lookup_law;

/* The law at (p, h, theta): lookup_law_eval. */
typedef struct lookup_value {
    double flux;                 /* |h| at which k is evaluated [W/m^2] (bound if clamped) */
    double jump;                 /* temperature jump [K] */
    double jump_std;             /* its ensemble standard deviation [K] */
    double jump_error;           /* its estimated discretization error [K] (0: flag NO_ERROR_ESTIMATE) */
    double d_jump_dp;            /* d jump / d p [K/Pa] */
    double d_jump_dh;            /* d jump / d |h| [K m^2/W] */
    double d_jump_dtheta;        /* d jump / d theta_c [-] */
    double conductance;          /* k = |h| / jump [W/(m^2 K)] */
    double d_conductance_dp;     /* d k / d p */
    double d_conductance_dh;     /* d k / d |h| */
    double d_conductance_dtheta; /* d k / d theta_c */
    uint32_t flags;              /* LOOKUP_FLAG_* */
    uint32_t reserved;
} lookup_value;

/* The law at a given jump (p, jump, theta): lookup_law_eval_at_jump.
 * Derivatives are at fixed jump (resp. fixed p, theta): the tangent of a
 * GAPCON-style routine that knows the two surface temperatures. */
typedef struct lookup_flux_value {
    double flux;                 /* |h| producing the jump [W/m^2] */
    double jump_std;             /* ensemble standard deviation of the jump there [K] */
    double jump_error;           /* estimated discretization error of the jump there [K] */
    double conductance;          /* k = |h| / jump [W/(m^2 K)] */
    double d_flux_dp;
    double d_flux_djump;         /* thermal tangent of the interface */
    double d_flux_dtheta;
    double d_conductance_dp;     /* Abaqus GAPCON AK(3) */
    double d_conductance_djump;
    double d_conductance_dtheta;
    uint32_t flags;              /* LOOKUP_FLAG_* */
    uint32_t reserved;
} lookup_flux_value;

/* Opens a law file; NULL on failure (*status, if not NULL, gets the code). */
lookup_law *lookup_law_open(const char *path, int32_t *status);

/* Builds a law from a grid: jump_mean and jump_std hold n_p*n_h*n_theta values,
 * contact temperature fastest ([pressure][flux][contact_temperature]).
 * jump_std may be NULL (zeros). ensemble_size 0: deterministic; >= 1: ensemble
 * mean of that many samples. extrapolation: LOOKUP_EXTRAPOLATE_* for all axes. */
lookup_law *lookup_law_from_grid(size_t n_p, const double *pressure,
                                 size_t n_h, const double *flux,
                                 size_t n_theta, const double *contact_temperature,
                                 const double *jump_mean, const double *jump_std,
                                 uint32_t ensemble_size, int32_t extrapolation,
                                 int32_t *status);

/* Writes the law file. */
int32_t lookup_law_write(const lookup_law *law, const char *path);

/* Evaluates at pressure p [Pa], flux magnitude h [W/m^2], contact temperature
 * theta [K]. On failure *out is zeroed. Never allocates. */
int32_t lookup_law_eval(const lookup_law *law, double p, double h, double theta,
                        lookup_value *out);

/* Finds the flux giving temperature jump `jump` [K] at p and theta, and the
 * conductance there. Under the 'clamp' flux policy a jump below the table's
 * gives the conductance at the smallest flux (jump 0 is fine). */
int32_t lookup_law_eval_at_jump(const lookup_law *law, double p, double jump,
                                double theta, lookup_flux_value *out);

/* Overrides the extrapolation policy of one axis (LOOKUP_AXIS_*, or
 * LOOKUP_AXIS_ALL) with LOOKUP_EXTRAPOLATE_* (POWER: pressure only). */
int32_t lookup_law_set_extrapolation(lookup_law *law, int32_t axis, int32_t policy);

/* Checks the caller's material of body LOOKUP_BODY_UPPER or LOOKUP_BODY_LOWER
 * against the law's: properties[6] = {E [Pa], nu, alpha0 [1/K], k0 [W/(m K)],
 * k1 [W/(m K^2)], theta0 [K]}. LOOKUP_ERR_MATERIAL_MISMATCH (message names the
 * property) if one differs by more than rel_tol (relative), or if the law
 * records no material. */
int32_t lookup_law_check_material(const lookup_law *law, int32_t body,
                                  const double *properties, double rel_tol);

/* Caps the conductance at k_max > 0 (where the jump vanishes too); 0 removes the cap. */
int32_t lookup_law_set_max_conductance(lookup_law *law, double k_max);

/* Number of nodes and range of one axis; n, min, max may be NULL. */
int32_t lookup_law_axis(const lookup_law *law, int32_t axis, size_t *n,
                        double *min, double *max);

/* Frees a law (NULL is ignored). */
void lookup_law_free(lookup_law *law);

/* Message of the last failing call in this thread, copied into buf
 * (NUL-terminated, truncated to len - 1); returns the full length. */
size_t lookup_last_error(char *buf, size_t len);

/* Static name of a status code, e.g. "LOOKUP_ERR_OUT_OF_RANGE". */
const char *lookup_status_name(int32_t status);

/* Law file format version written by this library (it reads 1 to this). */
uint32_t lookup_format_version(void);

#ifdef __cplusplus
}
#endif

#endif /* LOOKUP_H */
