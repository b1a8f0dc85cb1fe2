#include <gtest/gtest.h>

// Replaced by the turning tests.
TEST(PartsPlaceholder, Turning) {}
