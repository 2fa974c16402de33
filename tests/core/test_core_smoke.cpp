#include <gtest/gtest.h>
#include "starnav/core/rng.hpp"
TEST(Smoke, Rng) { starnav::Rng r(1); EXPECT_NE(r.next(), r.next()); }
