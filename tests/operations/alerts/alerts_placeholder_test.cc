// Placeholder until the alerts tests land; removed with them.
#include <gtest/gtest.h>
