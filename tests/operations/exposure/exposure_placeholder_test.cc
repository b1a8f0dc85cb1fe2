// Placeholder until the exposure tests land; removed with them.
#include <gtest/gtest.h>
