/*
 * cholmod_peer: time SuiteSparse (AMD ordering, CHOLMOD simplicial and
 * supernodal Cholesky) on one symmetric positive definite matrix, so the
 * crate's own ordering and factorization can be compared side by side.
 *
 *   cholmod_peer MATRIX.mtx [REPEATS] [--json]
 *
 * MATRIX.mtx is a symmetric Matrix Market coordinate file (one triangle).
 * The right-hand side is MATRIX.b.mtx (an n x k array) when it exists next
 * to the matrix, otherwise a synthetic n x 3 block. Every figure is the
 * median of REPEATS runs (default 20), on one thread: the program re-executes
 * itself with OMP_NUM_THREADS=1, OMP_THREAD_LIMIT=1 and
 * OPENBLAS_NUM_THREADS=1 unless they are set already.
 *
 * What is timed (wall clock, CLOCK_MONOTONIC):
 *   amd            amd_order on the matrix as stored (one triangle; AMD
 *                  forms the pattern of A + A' itself)
 *   analyze        cholmod_analyze with AMD forced (nmethods = 1) and a
 *                  postorder, simplicial or supernodal
 *   numeric        cholmod_factorize into an already factored L (the
 *                  values are recomputed, the memory is reused)
 *   solve          cholmod_solve2 (A, L, B) with all k columns at once,
 *                  workspace reused between runs
 * nnz(L) counts include the diagonal and come from CHOLMOD's symbolic
 * analysis (exact), not from AMD's estimate Info[AMD_LNZ] (an upper bound),
 * which is printed beside it.
 */

#define _GNU_SOURCE
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <unistd.h>

#include <amd.h>
#include <cholmod.h>

#define DEFAULT_REPEATS 20
#define MAX_REPEATS 100000

/* ------------------------------------------------------------------ util */

static void die(const char *message, const char *detail)
{
    fprintf(stderr, "cholmod_peer: %s%s%s\n", message, detail ? ": " : "",
            detail ? detail : "");
    exit(1);
}

static double now_seconds(void)
{
    struct timespec t;
    clock_gettime(CLOCK_MONOTONIC, &t);
    return (double)t.tv_sec + 1e-9 * (double)t.tv_nsec;
}

static int compare_doubles(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

/* Median of times[0..count); sorts the array. */
static double median(double *times, int count)
{
    qsort(times, (size_t)count, sizeof(double), compare_doubles);
    return count % 2 ? times[count / 2]
                     : 0.5 * (times[count / 2 - 1] + times[count / 2]);
}

/* Re-executes the program with every threading knob at 1, once. */
static void ensure_single_thread(char **argv)
{
    const char *set = getenv("OMP_THREAD_LIMIT");
    if (set && strcmp(set, "1") == 0)
        return;
    setenv("OMP_NUM_THREADS", "1", 1);
    setenv("OMP_THREAD_LIMIT", "1", 1);
    setenv("OPENBLAS_NUM_THREADS", "1", 1);
    setenv("MKL_NUM_THREADS", "1", 1);
    execv("/proc/self/exe", argv);
    fprintf(stderr, "cholmod_peer: could not re-execute with one thread; "
                    "set OMP_THREAD_LIMIT=1 OMP_NUM_THREADS=1 yourself\n");
}

/* Number of threads of this process (from /proc), -1 if unknown. */
static int thread_count(void)
{
    FILE *f = fopen("/proc/self/status", "r");
    char line[256];
    int threads = -1;
    if (!f)
        return -1;
    while (fgets(line, sizeof line, f))
        if (sscanf(line, "Threads: %d", &threads) == 1)
            break;
    fclose(f);
    return threads;
}

/* Path of the BLAS library mapped into this process, or "unknown". */
static const char *loaded_blas(void)
{
    static char path[512] = "unknown";
    char line[1024];
    FILE *f = fopen("/proc/self/maps", "r");
    if (!f)
        return path;
    while (fgets(line, sizeof line, f)) {
        char *file = strchr(line, '/');
        if (file && strstr(file, "blas")) {
            file[strcspn(file, "\n")] = '\0';
            snprintf(path, sizeof path, "%s", file);
            break;
        }
    }
    fclose(f);
    return path;
}

/* --------------------------------------------------------------- inputs */

static cholmod_sparse *read_symmetric_matrix(const char *path, cholmod_common *c)
{
    FILE *f = fopen(path, "r");
    if (!f)
        die("cannot open the matrix", path);
    cholmod_sparse *A = cholmod_read_sparse(f, c);
    fclose(f);
    if (!A)
        die("not a Matrix Market sparse matrix CHOLMOD can read", path);
    if (A->stype == 0 || A->nrow != A->ncol || A->xtype != CHOLMOD_REAL)
        die("the matrix must be a real symmetric Matrix Market file", path);
    return A;
}

/* "DIR/NAME.mtx" -> "DIR/NAME.b.mtx" (or "PATH.b.mtx" without ".mtx"). */
static char *rhs_path_for(const char *matrix_path)
{
    size_t length = strlen(matrix_path);
    char *path = malloc(length + 8);
    if (!path)
        die("out of memory", NULL);
    strcpy(path, matrix_path);
    if (length >= 4 && strcmp(path + length - 4, ".mtx") == 0)
        path[length - 4] = '\0';
    strcat(path, ".b.mtx");
    return path;
}

/* B(i, k) in [1, 2): varied but smooth enough to be representative. */
static cholmod_dense *synthetic_rhs(size_t n, cholmod_common *c)
{
    cholmod_dense *B = cholmod_allocate_dense(n, 3, n, CHOLMOD_REAL, c);
    double *b = B->x;
    for (size_t k = 0; k < 3; k++)
        for (size_t i = 0; i < n; i++)
            b[i + k * n] = 1.0 + (double)((i * (k + 2)) % 17) / 17.0;
    return B;
}

/* The right-hand side next to the matrix if there is one, else synthetic. */
static cholmod_dense *read_rhs(const char *matrix_path, size_t n,
                               const char **source, cholmod_common *c)
{
    char *path = rhs_path_for(matrix_path);
    FILE *f = fopen(path, "r");
    if (!f) {
        free(path);
        *source = "synthetic";
        return synthetic_rhs(n, c);
    }
    cholmod_dense *B = cholmod_read_dense(f, c);
    fclose(f);
    if (!B || B->nrow != n || B->ncol == 0)
        die("the right-hand side must be an n x k Matrix Market array", path);
    *source = path; /* kept for the report */
    return B;
}

/* --------------------------------------------------------------- timing */

struct amd_result {
    double seconds;
    double info_lnz; /* Info[AMD_LNZ] + n: AMD's own (upper bound) estimate */
    int *perm;
};

static struct amd_result time_amd(cholmod_sparse *A, int repeats, double *times)
{
    int n = (int)A->ncol;
    double control[AMD_CONTROL], info[AMD_INFO];
    struct amd_result result = {0, 0, malloc(sizeof(int) * (size_t)(n + 1))};
    amd_defaults(control);
    for (int r = 0; r < repeats; r++) {
        double start = now_seconds();
        int status = amd_order(n, A->p, A->i, result.perm, control, info);
        times[r] = now_seconds() - start;
        if (status != AMD_OK && status != AMD_OK_BUT_JUMBLED)
            die("amd_order failed", NULL);
    }
    result.seconds = median(times, repeats);
    result.info_lnz = info[AMD_LNZ] + n;
    return result;
}

/* Exact nnz(L), diagonal included, for the permutation perm. */
static double nnz_l_for_permutation(cholmod_sparse *A, int *perm, cholmod_common *c)
{
    int saved_ordering = c->method[0].ordering;
    c->method[0].ordering = CHOLMOD_GIVEN;
    cholmod_factor *L = cholmod_analyze_p(A, perm, NULL, 0, c);
    if (!L)
        die("cholmod_analyze_p failed", NULL);
    double lnz = c->lnz;
    cholmod_free_factor(&L, c);
    c->method[0].ordering = saved_ordering;
    return lnz;
}

struct factor_result {
    double analyze_s, numeric_s, solve_s;
    double nnz_l;    /* exact, diagonal included */
    double stored_l; /* entries stored (supernodal: with padding) */
    double residual; /* |A X - B|_F / |B|_F */
};

static void use_cholmod_amd(cholmod_common *c, int supernodal)
{
    c->nmethods = 1;
    c->method[0].ordering = CHOLMOD_AMD;
    c->postorder = 1;
    c->supernodal = supernodal ? CHOLMOD_SUPERNODAL : CHOLMOD_SIMPLICIAL;
    c->final_ll = 1;
}

static cholmod_factor *time_analyze(cholmod_sparse *A, int repeats, double *times,
                                    struct factor_result *result, cholmod_common *c)
{
    cholmod_factor *L = NULL;
    for (int r = 0; r < repeats; r++) {
        if (L)
            cholmod_free_factor(&L, c);
        double start = now_seconds();
        L = cholmod_analyze(A, c);
        times[r] = now_seconds() - start;
        if (!L)
            die("cholmod_analyze failed", NULL);
    }
    result->analyze_s = median(times, repeats);
    result->nnz_l = c->lnz;
    return L;
}

/* Entries L holds: with the padding of relaxed supernodes if supernodal. */
static double stored_entries(const cholmod_factor *L)
{
    if (L->is_super)
        return (double)L->xsize;
    double total = 0;
    for (size_t j = 0; j < L->n; j++)
        total += ((const int *)L->nz)[j];
    return total;
}

static void factorize_checked(cholmod_sparse *A, cholmod_factor *L, cholmod_common *c)
{
    if (!cholmod_factorize(A, L, c) || c->status != CHOLMOD_OK)
        die("cholmod_factorize failed (is the matrix positive definite?)", NULL);
}

static double frobenius_norm(const cholmod_dense *X)
{
    const double *x = X->x;
    double sum = 0;
    for (size_t k = 0; k < X->ncol; k++)
        for (size_t i = 0; i < X->nrow; i++)
            sum += x[i + k * X->d] * x[i + k * X->d];
    return sqrt(sum);
}

/* |A X - B|_F / |B|_F, with A symmetric (one triangle stored). */
static double relative_residual(cholmod_sparse *A, cholmod_dense *X, cholmod_dense *B,
                                cholmod_common *c)
{
    cholmod_dense *R = cholmod_copy_dense(B, c);
    double one[2] = {1, 0}, minus_one[2] = {-1, 0};
    cholmod_sdmult(A, 0, one, minus_one, X, R, c); /* R = A X - B */
    double residual = frobenius_norm(R) / frobenius_norm(B);
    cholmod_free_dense(&R, c);
    return residual;
}

static struct factor_result time_cholmod(cholmod_sparse *A, cholmod_dense *B, int supernodal,
                                         int repeats, double *times, cholmod_common *c)
{
    struct factor_result result = {0};
    use_cholmod_amd(c, supernodal);
    cholmod_factor *L = time_analyze(A, repeats, times, &result, c);

    factorize_checked(A, L, c); /* first factorization allocates L's values */
    for (int r = 0; r < repeats; r++) {
        double start = now_seconds();
        factorize_checked(A, L, c);
        times[r] = now_seconds() - start;
    }
    result.numeric_s = median(times, repeats);
    result.stored_l = stored_entries(L);

    cholmod_dense *X = NULL, *Y = NULL, *E = NULL;
    cholmod_solve2(CHOLMOD_A, L, B, NULL, &X, NULL, &Y, &E, c); /* allocates workspace */
    for (int r = 0; r < repeats; r++) {
        double start = now_seconds();
        int ok = cholmod_solve2(CHOLMOD_A, L, B, NULL, &X, NULL, &Y, &E, c);
        times[r] = now_seconds() - start;
        if (!ok)
            die("cholmod_solve2 failed", NULL);
    }
    result.solve_s = median(times, repeats);
    result.residual = relative_residual(A, X, B, c);

    cholmod_free_dense(&X, c);
    cholmod_free_dense(&Y, c);
    cholmod_free_dense(&E, c);
    cholmod_free_factor(&L, c);
    return result;
}

/* --------------------------------------------------------------- report */

struct report {
    const char *matrix, *rhs, *blas;
    size_t n, rhs_columns;
    double nnz_stored;
    int repeats, threads;
    struct amd_result amd;
    double amd_nnz_l;
    struct factor_result simplicial, supernodal;
};

static void print_table(const struct report *r)
{
    const double ms = 1e3;
    printf("matrix           %s\n", r->matrix);
    printf("n                %zu\n", r->n);
    printf("nnz(Q lower)     %.0f\n", r->nnz_stored);
    printf("right-hand side  %s (%zu columns)\n", r->rhs, r->rhs_columns);
    printf("BLAS             %s\n", r->blas);
    printf("runs             medians of %d, %d thread(s)\n\n", r->repeats, r->threads);
    printf("%-22s %12s %12s %12s %12s\n", "", "order/analyze", "numeric", "solve", "nnz(L)");
    printf("%-22s %10.3f ms %12s %12s %12.0f   (AMD's estimate %.0f)\n", "SuiteSparse AMD",
           r->amd.seconds * ms, "", "", r->amd_nnz_l, r->amd.info_lnz);
    printf("%-22s %10.3f ms %9.3f ms %9.3f ms %12.0f\n", "CHOLMOD simplicial LL'",
           r->simplicial.analyze_s * ms, r->simplicial.numeric_s * ms,
           r->simplicial.solve_s * ms, r->simplicial.nnz_l);
    printf("%-22s %10.3f ms %9.3f ms %9.3f ms %12.0f   (stored %.0f)\n",
           "CHOLMOD supernodal LL'", r->supernodal.analyze_s * ms,
           r->supernodal.numeric_s * ms, r->supernodal.solve_s * ms, r->supernodal.nnz_l,
           r->supernodal.stored_l);
    printf("\nrelative residual |QX - B|/|B|: simplicial %.2e, supernodal %.2e\n",
           r->simplicial.residual, r->supernodal.residual);
}

static void print_json_string(const char *key, const char *value)
{
    printf("\"%s\": \"", key);
    for (const char *p = value; *p; p++) {
        if (*p == '"' || *p == '\\')
            putchar('\\');
        if ((unsigned char)*p < 0x20)
            printf("\\u%04x", *p);
        else
            putchar(*p);
    }
    printf("\", ");
}

static void print_json(const struct report *r)
{
    printf("{");
    print_json_string("matrix", r->matrix);
    print_json_string("rhs", r->rhs);
    print_json_string("blas", r->blas);
    printf("\"n\": %zu, \"nnz_lower\": %.0f, \"rhs_columns\": %zu, \"repeats\": %d, "
           "\"threads\": %d, ",
           r->n, r->nnz_stored, r->rhs_columns, r->repeats, r->threads);
    printf("\"amd_s\": %.9g, \"amd_nnz_l\": %.0f, \"amd_info_nnz_l\": %.0f, ", r->amd.seconds,
           r->amd_nnz_l, r->amd.info_lnz);
    printf("\"simplicial_analyze_s\": %.9g, \"simplicial_numeric_s\": %.9g, "
           "\"simplicial_solve_s\": %.9g, \"simplicial_nnz_l\": %.0f, ",
           r->simplicial.analyze_s, r->simplicial.numeric_s, r->simplicial.solve_s,
           r->simplicial.nnz_l);
    printf("\"supernodal_analyze_s\": %.9g, \"supernodal_numeric_s\": %.9g, "
           "\"supernodal_solve_s\": %.9g, \"supernodal_nnz_l\": %.0f, "
           "\"supernodal_stored_l\": %.0f, ",
           r->supernodal.analyze_s, r->supernodal.numeric_s, r->supernodal.solve_s,
           r->supernodal.nnz_l, r->supernodal.stored_l);
    printf("\"residual\": %.3e, \"supernodal_residual\": %.3e}\n", r->simplicial.residual,
           r->supernodal.residual);
}

/* ----------------------------------------------------------------- main */

static void usage(void)
{
    fprintf(stderr, "usage: cholmod_peer MATRIX.mtx [REPEATS] [--json]\n"
                    "  MATRIX.mtx: symmetric Matrix Market file; MATRIX.b.mtx (n x k array),\n"
                    "  if present, is the right-hand side. REPEATS defaults to %d.\n",
            DEFAULT_REPEATS);
    exit(2);
}

int main(int argc, char **argv)
{
    const char *matrix_path = NULL;
    int repeats = DEFAULT_REPEATS, json = 0, positional = 0;
    for (int a = 1; a < argc; a++) {
        if (strcmp(argv[a], "--json") == 0)
            json = 1;
        else if (argv[a][0] == '-')
            usage();
        else if (positional++ == 0)
            matrix_path = argv[a];
        else if (positional == 2) {
            char *end;
            long value = strtol(argv[a], &end, 10);
            if (*end || value < 1 || value > MAX_REPEATS)
                usage();
            repeats = (int)value;
        } else
            usage();
    }
    if (!matrix_path)
        usage();
    ensure_single_thread(argv);

    cholmod_common common, *c = &common;
    cholmod_start(c);
    struct report r = {.matrix = matrix_path, .repeats = repeats};
    double *times = malloc(sizeof(double) * (size_t)repeats);

    cholmod_sparse *A = read_symmetric_matrix(matrix_path, c);
    cholmod_dense *B = read_rhs(matrix_path, A->nrow, &r.rhs, c);
    r.n = A->nrow;
    r.nnz_stored = (double)cholmod_nnz(A, c);
    r.rhs_columns = B->ncol;

    r.amd = time_amd(A, repeats, times);
    use_cholmod_amd(c, 0);
    r.amd_nnz_l = nnz_l_for_permutation(A, r.amd.perm, c);
    r.simplicial = time_cholmod(A, B, 0, repeats, times, c);
    r.supernodal = time_cholmod(A, B, 1, repeats, times, c);
    r.threads = thread_count();
    r.blas = loaded_blas();

    if (json)
        print_json(&r);
    else
        print_table(&r);
    if (r.threads != 1)
        fprintf(stderr, "cholmod_peer: warning: the process has %d threads\n", r.threads);

    free(r.amd.perm);
    free(times);
    cholmod_free_dense(&B, c);
    cholmod_free_sparse(&A, c);
    cholmod_finish(c);
    return 0;
}
