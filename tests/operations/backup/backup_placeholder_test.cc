// Placeholder until the backup tests land; removed with them.
#include <gtest/gtest.h>
