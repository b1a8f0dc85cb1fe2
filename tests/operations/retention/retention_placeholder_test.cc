// Placeholder until the retention tests land; removed with them.
#include <gtest/gtest.h>
