#include <gtest/gtest.h>

// Replaced by the plates tests.
TEST(PartsPlaceholder, Plates) {}
