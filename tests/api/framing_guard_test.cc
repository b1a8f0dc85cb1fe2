// Filled in by the change that adds its behaviour.
#include <gtest/gtest.h>
