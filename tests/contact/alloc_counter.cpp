// The counting operator new of the test_contact binary (tests/common/alloc_counter.hpp).
#define DSDEM_DEFINE_ALLOC_COUNTER
#include "common/alloc_counter.hpp"
