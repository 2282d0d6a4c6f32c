/* A strand of an example hairstyle at rest on the example head, for the dynamics
 * tests. */
#ifndef HK_TEST_STRAND_H
#define HK_TEST_STRAND_H

#include "hairkit/io.h"
#include "hairkit/rod.h"

/* Loads examples/strand/TYPE.txt into *def, grows its strand from the crown of the
 * head of examples/strand/head.txt (shapes, count: loaded by the caller) and solves
 * its statics rest shape in the envelope alpha = 0.5, as a groomed head starts; *body
 * receives that environment. Fails the test on any error. */
hk_SuperHelix *hk_test_strand_on_head(const char *type, const hk_Shape *shapes, int count, hk_Hairstyle *def,
                                      hk_StrandEnvDef *body);

#endif
