/*
 * C test of the lookup C ABI, compiled and run by lookup/tests/c_abi.rs.
 *
 * Usage: test_lookup DIR
 * Builds a law linear in (ln p, h, theta), checks values and derivatives,
 * writes DIR/c_written.tclaw, reopens it, checks the error paths, runs a
 * GAPCON-style conductance routine, and prints "value ..." lines (%.17g) that
 * the Rust side compares bit for bit with its own evaluation of the same file.
 * Exit status 0 only if every check passed.
 */
#include "lookup.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static int passed = 0, failed = 0;

#define CHECK(cond, ...)                                         \
    do {                                                         \
        if (cond) {                                              \
            passed++;                                            \
        } else {                                                 \
            failed++;                                            \
            printf("FAILED line %d: %s: ", __LINE__, #cond);     \
            printf(__VA_ARGS__);                                 \
            printf("\n");                                        \
        }                                                        \
    } while (0)

static int close_to(double a, double b, double rel) {
    return fabs(a - b) <= rel * fmax(fabs(a), fabs(b));
}

/* Data linear in (ln p, h, theta). */
static double linear_jump(double p, double h, double t) {
    return 200.0 - 3.0 * log(p) + 2e-5 * h + 0.1 * t;
}

/*
 * A GAPCON-style routine (Abaqus/CalculiX semantics): d[1] contact pressure,
 * temp[0] slave (body 1) and temp[1] master (body 2) temperatures. Returns the
 * status; ak[0] = conductance, ak[2] = d conductance / d pressure.
 */
static int32_t gapcon(const lookup_law *law, double ak[5], const double d[2],
                      const double temp[2]) {
    lookup_flux_value v;
    double jump = fabs(temp[0] - temp[1]);
    int32_t s = lookup_law_eval_at_jump(law, d[1], jump, temp[1], &v);
    ak[0] = v.conductance;
    ak[1] = 0.0;
    ak[2] = v.d_conductance_dp;
    return s;
}

int main(int argc, char **argv) {
    char path[4096], bad_path[4096], msg[512];
    const double pressure[4] = {1e4, 1e5, 1e6, 1e7};
    const double flux[3] = {1e4, 1e5, 1e6};
    const double theta[2] = {290.0, 400.0};
    double mean[24], std_dev[24];
    int32_t status = -1;
    size_t i, j, k, n;

    if (argc < 2) {
        fprintf(stderr, "usage: test_lookup DIR\n");
        return 2;
    }
    snprintf(path, sizeof path, "%s/c_written.tclaw", argv[1]);
    snprintf(bad_path, sizeof bad_path, "%s/c_corrupted.tclaw", argv[1]);

    printf("sizeof lookup_value %zu\n", sizeof(lookup_value));
    printf("sizeof lookup_flux_value %zu\n", sizeof(lookup_flux_value));
    printf("format_version %u\n", lookup_format_version());
    printf("status LOOKUP_ERR_OUT_OF_RANGE %d %s\n", LOOKUP_ERR_OUT_OF_RANGE,
           lookup_status_name(LOOKUP_ERR_OUT_OF_RANGE));
    printf("status LOOKUP_ERR_PANIC %d %s\n", LOOKUP_ERR_PANIC,
           lookup_status_name(LOOKUP_ERR_PANIC));

    for (i = 0; i < 4; i++)
        for (j = 0; j < 3; j++)
            for (k = 0; k < 2; k++) {
                mean[(i * 3 + j) * 2 + k] = linear_jump(pressure[i], flux[j], theta[k]);
                std_dev[(i * 3 + j) * 2 + k] = 0.01 * (double)(i + j + k);
            }

    /* Build, evaluate, check exactness on linear data. */
    lookup_law *law = lookup_law_from_grid(4, pressure, 3, flux, 2, theta, mean, std_dev,
                                           16, LOOKUP_EXTRAPOLATE_ERROR, &status);
    CHECK(law != NULL && status == LOOKUP_OK, "from_grid status %d", status);
    if (law == NULL) return 1;

    lookup_value v;
    double p = 3.3e5, h = 4.2e5, t = 333.0;
    CHECK(lookup_law_eval(law, p, h, t, &v) == LOOKUP_OK, "eval");
    CHECK(close_to(v.jump, linear_jump(p, h, t), 1e-12), "jump %.17g", v.jump);
    CHECK(close_to(v.d_jump_dp, -3.0 / p, 1e-10), "d_jump_dp %.17g", v.d_jump_dp);
    CHECK(close_to(v.d_jump_dh, 2e-5, 1e-9), "d_jump_dh %.17g", v.d_jump_dh);
    CHECK(close_to(v.d_jump_dtheta, 0.1, 1e-9), "d_jump_dtheta %.17g", v.d_jump_dtheta);
    CHECK(close_to(v.conductance, h / v.jump, 1e-14), "k %.17g", v.conductance);
    CHECK(v.flags == LOOKUP_FLAG_NO_ERROR_ESTIMATE && v.jump_error == 0.0, "flags %u", v.flags);

    /* Write, reopen, same values. */
    CHECK(lookup_law_write(law, path) == LOOKUP_OK, "write");
    lookup_law *back = lookup_law_open(path, &status);
    CHECK(back != NULL && status == LOOKUP_OK, "open status %d", status);
    if (back == NULL) return 1;
    lookup_value w;
    CHECK(lookup_law_eval(back, p, h, t, &w) == LOOKUP_OK, "eval reopened");
    CHECK(memcmp(&v, &w, sizeof v) == 0, "reopened law differs");

    /* Axis ranges. */
    double lo = 0, hi = 0;
    CHECK(lookup_law_axis(back, LOOKUP_AXIS_PRESSURE, &n, &lo, &hi) == LOOKUP_OK, "axis");
    CHECK(n == 4 && lo == 1e4 && hi == 1e7, "axis n %zu lo %g hi %g", n, lo, hi);
    CHECK(lookup_law_axis(back, 7, &n, &lo, &hi) == LOOKUP_ERR_INVALID_ARGUMENT, "bad axis");

    /* Error paths: NaN, out of range (policy from the file), override, bad codes. */
    CHECK(lookup_law_eval(back, NAN, h, t, &w) == LOOKUP_ERR_NON_FINITE, "nan");
    CHECK(w.conductance == 0.0, "out not zeroed on failure");
    CHECK(lookup_law_eval(back, p, h, INFINITY, &w) == LOOKUP_ERR_NON_FINITE, "inf");
    CHECK(lookup_law_eval(back, -5.0, h, t, &w) == LOOKUP_ERR_INVALID_QUERY, "negative p");
    CHECK(lookup_law_eval(back, 1e9, h, t, &w) == LOOKUP_ERR_OUT_OF_RANGE, "out of range");
    n = lookup_last_error(msg, sizeof msg);
    CHECK(n > 0 && strstr(msg, "pressure") != NULL, "message '%s'", msg);
    printf("message out_of_range %s\n", msg);
    n = lookup_last_error(msg, 8);
    CHECK(n > 8 && strlen(msg) == 7, "truncation: n %zu, '%s'", n, msg);
    CHECK(lookup_law_set_extrapolation(back, LOOKUP_AXIS_PRESSURE, LOOKUP_EXTRAPOLATE_CLAMP) ==
              LOOKUP_OK, "set clamp");
    CHECK(lookup_law_eval(back, 1e9, h, t, &w) == LOOKUP_OK, "clamped eval");
    CHECK(w.flags == (LOOKUP_FLAG_EXTRAPOLATED_PRESSURE | LOOKUP_FLAG_NO_ERROR_ESTIMATE) &&
              w.d_jump_dp == 0.0, "flags %u", w.flags);
    /* Power continuation: pressure only. */
    CHECK(lookup_law_set_extrapolation(back, LOOKUP_AXIS_PRESSURE, LOOKUP_EXTRAPOLATE_POWER) ==
              LOOKUP_OK, "set power");
    CHECK(lookup_law_eval(back, 1e9, h, t, &w) == LOOKUP_OK && w.jump > 0.0, "power eval");
    CHECK(lookup_law_set_extrapolation(back, LOOKUP_AXIS_FLUX, LOOKUP_EXTRAPOLATE_POWER) ==
              LOOKUP_ERR_INVALID_ARGUMENT, "power on flux");
    CHECK(lookup_law_set_extrapolation(back, LOOKUP_AXIS_PRESSURE, LOOKUP_EXTRAPOLATE_CLAMP) ==
              LOOKUP_OK, "back to clamp");
    /* A law built from a grid records no material. */
    {
        const double steel[6] = {2.1e11, 0.3, 1.2e-5, 45.0, 0.0, 293.15};
        CHECK(lookup_law_check_material(back, LOOKUP_BODY_UPPER, steel, 1e-6) ==
                  LOOKUP_ERR_MATERIAL_MISMATCH, "no material recorded");
        lookup_last_error(msg, sizeof msg);
        CHECK(strstr(msg, "no material") != NULL, "message '%s'", msg);
        CHECK(lookup_law_check_material(back, 3, steel, 1e-6) == LOOKUP_ERR_INVALID_ARGUMENT,
              "bad body");
    }
    CHECK(lookup_law_set_extrapolation(back, LOOKUP_AXIS_ALL, 9) == LOOKUP_ERR_INVALID_ARGUMENT,
          "bad policy");
    CHECK(lookup_law_set_max_conductance(back, -1.0) == LOOKUP_ERR_INVALID_ARGUMENT, "bad cap");
    CHECK(lookup_law_eval(NULL, p, h, t, &w) == LOOKUP_ERR_NULL_ARGUMENT, "null law");
    CHECK(lookup_law_eval(back, p, h, t, NULL) == LOOKUP_ERR_NULL_ARGUMENT, "null out");

    /* Files: missing, corrupted. */
    CHECK(lookup_law_open("/nonexistent/dir/law.tclaw", &status) == NULL &&
              status == LOOKUP_ERR_IO, "missing file status %d", status);
    {
        FILE *f = fopen(path, "rb");
        unsigned char buf[8192];
        size_t len = f ? fread(buf, 1, sizeof buf, f) : 0;
        if (f) fclose(f);
        CHECK(len > 100, "read back %zu bytes", len);
        buf[len - 40] ^= 0x01;
        f = fopen(bad_path, "wb");
        if (f) {
            fwrite(buf, 1, len, f);
            fclose(f);
        }
        CHECK(lookup_law_open(bad_path, &status) == NULL && status == LOOKUP_ERR_CHECKSUM,
              "corrupted file status %d", status);
        lookup_last_error(msg, sizeof msg);
        printf("message corrupted %s\n", msg);
    }

    /* GAPCON-style conductance from the surface temperatures. */
    {
        double ak[5] = {0}, d[2] = {0.0, p}, temp[2];
        lookup_flux_value f;
        temp[1] = t;
        temp[0] = t + v.jump; /* the jump the law gives at flux h */
        CHECK(gapcon(back, ak, d, temp) == LOOKUP_OK, "gapcon");
        CHECK(close_to(ak[0], v.conductance, 1e-9), "AK(1) %.17g vs %.17g", ak[0], v.conductance);
        CHECK(lookup_law_eval_at_jump(back, p, v.jump, t, &f) == LOOKUP_OK, "eval_at_jump");
        CHECK(close_to(f.flux, h, 1e-9), "flux %.17g", f.flux);
        printf("gapcon AK1 %.17g AK3 %.17g\n", ak[0], ak[2]);
    }

    /* Values for the Rust side (pressure clamped on `back`, error elsewhere). */
    {
        const double q[4][3] = {{2e4, 1.5e4, 291.0}, {7.7e6, 9.9e5, 399.0},
                                {3.3e5, 4.2e5, 333.0}, {5e8, 5e5, 300.0}};
        for (i = 0; i < 4; i++) {
            int32_t s = lookup_law_eval(back, q[i][0], q[i][1], q[i][2], &w);
            printf("value %.17g %.17g %.17g %d %.17g %.17g %.17g %.17g %.17g %u\n", q[i][0],
                   q[i][1], q[i][2], s, w.jump, w.d_jump_dp, w.d_jump_dh, w.conductance,
                   w.d_conductance_dp, w.flags);
        }
    }

    lookup_law_free(law);
    lookup_law_free(back);
    lookup_law_free(NULL);
    printf("c-abi: %d passed, %d failed\n", passed, failed);
    return failed == 0 ? 0 : 1;
}
