/* The hardware floor of a reservoir harvest: x(t+1) = tanh(M^T x(t) + d(t)), one OpenBLAS sgemv
 * per tick, in C with no interpreter in the loop. Built by benchmarks/harvest_floor.py against
 * the OpenBLAS that numpy ships (its cblas_sgemv, found by name at run time with dlsym).
 * Usage: harvest_floor LIBOPENBLAS SYMBOL N T REPEATS  -> prints the best wall and process
 * CPU seconds per tick. */
#include <dlfcn.h>
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#ifndef BLASINT
#define BLASINT int64_t /* numpy's scipy-openblas64 is ILP64; -DBLASINT=int for LP64 builds */
#endif
typedef void (*sgemv64_t)(int order, int trans, BLASINT m, BLASINT n, float alpha,
                          const float *a, BLASINT lda, const float *x, BLASINT incx,
                          float beta, float *y, BLASINT incy);

static double clock_s(clockid_t id) {
    struct timespec ts;
    clock_gettime(id, &ts);
    return ts.tv_sec + 1e-9 * ts.tv_nsec;
}

int main(int argc, char **argv) {
    if (argc != 6) { fprintf(stderr, "usage: %s LIB SYMBOL N T REPEATS\n", argv[0]); return 2; }
    void *lib = dlopen(argv[1], RTLD_NOW);
    if (!lib) { fprintf(stderr, "%s\n", dlerror()); return 1; }
    sgemv64_t sgemv = (sgemv64_t)dlsym(lib, argv[2]);
    if (!sgemv) { fprintf(stderr, "%s\n", dlerror()); return 1; }
    int64_t n = atol(argv[3]), T = atol(argv[4]);
    int repeats = atoi(argv[5]);
    float *M = malloc(sizeof(float) * n * n), *d = malloc(sizeof(float) * n * T);
    float *x0 = malloc(sizeof(float) * n), *x, *y = malloc(sizeof(float) * n);
    float *states = malloc(sizeof(float) * n * T);
    srand(0);
    for (int64_t i = 0; i < n * n; i++) M[i] = (rand() / (float)RAND_MAX - 0.5f) * 0.08f;
    for (int64_t i = 0; i < n * T; i++) d[i] = (rand() / (float)RAND_MAX - 0.5f) * 0.2f;
    double best = 1e30, best_cpu = 1e30;
    for (int r = 0; r < repeats; r++) {
        memset(x0, 0, sizeof(float) * n);
        x = x0;
        double t0 = clock_s(CLOCK_MONOTONIC), c0 = clock_s(CLOCK_PROCESS_CPUTIME_ID);
        for (int64_t t = 0; t < T; t++) {
            memcpy(y, d + t * n, sizeof(float) * n);
            /* CblasRowMajor = 101, CblasTrans = 112: y = M^T x + y */
            sgemv(101, 112, n, n, 1.0f, M, n, x, 1, 1.0f, y, 1);
            float *s = states + t * n;
            for (int64_t i = 0; i < n; i++) s[i] = tanhf(y[i]);
            x = s;
        }
        double dt = (clock_s(CLOCK_MONOTONIC) - t0) / T;
        double dc = (clock_s(CLOCK_PROCESS_CPUTIME_ID) - c0) / T;
        if (dt < best) best = dt;
        if (dc < best_cpu) best_cpu = dc;
    }
    printf("%.9g %.9g\n", best, best_cpu);
    return 0;
}
