/* Shared helpers for the cmocka tests: temporary files and tolerant comparisons. */
#ifndef HK_TEST_H
#define HK_TEST_H

#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>

#include <cmocka.h>

/* Writes `size` bytes of `data` to a fresh file in a private temporary folder and
 * returns its path (static storage per call slot, valid until the process ends).
 * `name` is the file's base name, so error messages in tests look like real ones. */
const char *hk_test_write_file(const char *name, const void *data, size_t size);

/* Same for a NUL-terminated text. */
const char *hk_test_write_text(const char *name, const char *text);

/* Private temporary folder of this test process (created on first use). */
const char *hk_test_tmpdir(void);

/* The whole file at path (NUL-terminated, to free); its size in *size. */
char *hk_test_read_file(const char *path, size_t *size);

/* A light copy of the default scene (HairDensity 4: about 2,000 strands on the
 * 201-guide wick) whose setup names its files by absolute path; returns the setup's
 * path. */
const char *hk_test_light_setup(void);

/* The real grooms and heads of ../shared/hair-data (made by others, described in its
 * SOURCES.md, never copied into this repository). hk_test_have_shared_data: 1 when the
 * folder is there, else 0 after printing that the test is skipped (call skip() then).
 * hk_test_shared_path: the path of `name` in it (one of 4 static buffers in turn). */
int hk_test_have_shared_data(void);
const char *hk_test_shared_path(const char *name);

/* |a - b| <= tol; prints both values and the tolerance when it fails. */
#define hk_assert_near(a, b, tol) hk_assert_near_impl((a), (b), (tol), #a, #b, __FILE__, __LINE__)
void hk_assert_near_impl(double a, double b, double tol, const char *as, const char *bs, const char *file, int line);

/* |a - b| <= rtol * max(|a|, |b|, floor). */
#define hk_assert_rel(a, b, rtol, floor) hk_assert_rel_impl((a), (b), (rtol), (floor), #a, #b, __FILE__, __LINE__)
void hk_assert_rel_impl(double a, double b, double rtol, double floor, const char *as, const char *bs, const char *file,
                        int line);

/* Asserts that `haystack` contains `needle`, printing both when not. */
#define hk_assert_contains(haystack, needle) hk_assert_contains_impl((haystack), (needle), __FILE__, __LINE__)
void hk_assert_contains_impl(const char *haystack, const char *needle, const char *file, int line);

/* Deterministic uniform numbers in [0, 1) (xorshift64), for reproducible test data. */
double hk_test_uniform(void);

/* One random edit of buf[0..len) for the input fuzz loops: overwrite a byte with any
 * byte or with one of `plausible`, truncate, insert one of the `junk` strings, or
 * delete a span. `state` is a xorshift64 state (non-zero). Returns the new length,
 * never more than cap. */
size_t hk_test_mutate(char *buf, size_t len, size_t cap, const char *plausible, const char *const *junk, int junk_count,
                      unsigned long long *state);

#endif
