/* SPDX-License-Identifier: MIT */
/* The instruction-set choice of the hot loops (sim_isa*, sim/isa.c): names, refusals, and that a
 * world keeps the set it was created with. The bit equality of every set is test_golden's
 * isa_* cases. */
#include "sim_test_util.h"
#include "test.h"

#include <string.h>

static int names(void)
{
    for (int k = 0; k < SIM_ISA_COUNT; ++k) {
        const char *name = sim_isa_name((SimIsa)k);
        TEST_ASSERT(name != NULL);
        TEST_ASSERT(sim_isa_from_name(name) == k);
    }
    TEST_ASSERT(sim_isa_name(SIM_ISA_COUNT) == NULL);
    TEST_ASSERT(sim_isa_from_name("avx1024") == -1);
    TEST_ASSERT(sim_isa_from_name(NULL) == -1);
    TEST_ASSERT(strcmp(sim_isa_name(SIM_ISA_AVX512), "avx512") == 0);
    return 0;
}

static int choice(void)
{
    /* the default is a supported set, and at least one set is */
    TEST_ASSERT(sim_isa_supported(sim_isa()));
    TEST_ASSERT(sim_isa_set(SIM_ISA_COUNT) == SIM_ERROR_INVALID);
    int supported = 0;
    for (int k = 0; k < SIM_ISA_COUNT; ++k) {
        if (!sim_isa_supported((SimIsa)k)) {
            const SimIsa before = sim_isa();
            TEST_ASSERT(sim_isa_set((SimIsa)k) == SIM_ERROR_INVALID);
            TEST_ASSERT(sim_isa() == before);
            continue;
        }
        ++supported;
        TEST_ASSERT(sim_isa_set((SimIsa)k) == SIM_OK);
        TEST_ASSERT(sim_isa() == (SimIsa)k);
    }
    TEST_ASSERT(supported >= 1);
    /* a native build has its one path; any other has the baseline everywhere */
    TEST_ASSERT(sim_isa_supported(SIM_ISA_NATIVE) != sim_isa_supported(SIM_ISA_BASELINE));
    return 0;
}

TEST_MAIN(TEST_CASE(names), TEST_CASE(choice))
