#include <gtest/gtest.h>

// Replaced by the process tests.
TEST(PartsPlaceholder, Process) {}
