/* Points uniform by area on a mesh (src/mesh/mesh_sample.c). The reference is the
 * definition: a region of a mesh receives, in expectation, its share of the area, and a
 * point lies in the plane of its triangle with the blended normal there. */
#include "hk_test.h"

#include <math.h>
#include <string.h>

#include "hairkit/mesh.h"

static void test_uniform_by_area(void **state)
{
    (void)state;
    /* Two triangles of areas 1/2 (z = 0, x + y <= 1) and 3/2 (z = 1, scaled by sqrt 3). */
    const double k = sqrt(3.0);
    hk_Mesh m;
    hk_Error err;
    assert_int_equal(hk_mesh_alloc(&m, 6, 2, &err), HK_OK);
    const hk_Vec3 p[6] = {hk_v3(0, 0, 0), hk_v3(1, 0, 0), hk_v3(0, 1, 0),
                          hk_v3(0, 0, 1), hk_v3(k, 0, 1), hk_v3(0, k, 1)};
    memcpy(m.positions, p, sizeof p);
    for (int i = 0; i < 6; i++) m.normals[i] = hk_v3(0, 0, 1);
    const int tri[6] = {0, 1, 2, 3, 4, 5};
    memcpy(m.triangles, tri, sizeof tri);
    enum { N = 40000 };
    static hk_Vec3 a[N], n[N], b[N];
    assert_int_equal(hk_mesh_sample_uniform(&m, N, 7, 1, a, n, &err), HK_OK);
    long upper = 0, lower_left = 0;
    for (int i = 0; i < N; i++) {
        const double s = a[i].z > 0.5 ? k : 1.0;
        assert_true(a[i].x >= 0.0 && a[i].y >= 0.0 && a[i].x + a[i].y <= s * (1.0 + 1e-12));
        assert_true(a[i].z == 0.0 || a[i].z == 1.0);
        hk_assert_near(n[i].z, 1.0, 1e-15);
        upper += a[i].z > 0.5;
        lower_left += a[i].z < 0.5 && a[i].x < 0.5; /* 3/4 of the lower triangle's area */
    }
    /* Binomial: share 3/4 of the points on the upper triangle, sd sqrt(N p q) = 87. */
    assert_true(fabs((double)upper - 0.75 * N) < 5.0 * sqrt(N * 0.75 * 0.25));
    const double lower = N - (double)upper;
    assert_true(fabs((double)lower_left - 0.75 * lower) < 5.0 * sqrt(lower * 0.75 * 0.25));
    /* The same points whatever the threads; another seed gives others. */
    assert_int_equal(hk_mesh_sample_uniform(&m, N, 7, 2, b, NULL, &err), HK_OK);
    assert_memory_equal(a, b, sizeof a);
    assert_int_equal(hk_mesh_sample_uniform(&m, N, 8, 2, b, NULL, &err), HK_OK);
    assert_true(memcmp(a, b, sizeof a) != 0);
    /* No area: refused. */
    for (int i = 0; i < 6; i++) m.positions[i] = hk_v3(0, 0, 0);
    assert_int_equal(hk_mesh_sample_uniform(&m, 10, 7, 1, b, NULL, &err), HK_ERR_INVALID);
    hk_assert_contains(err.message, "no finite area");
    hk_mesh_free(&m);
}

int main(void)
{
    const struct CMUnitTest tests[] = {cmocka_unit_test(test_uniform_by_area)};
    return cmocka_run_group_tests(tests, NULL, NULL);
}
