#include <gtest/gtest.h>

// Replaced by the surfaces tests.
TEST(PartsPlaceholder, Surfaces) {}
