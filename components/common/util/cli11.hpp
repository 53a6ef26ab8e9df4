#pragma once
// CLI11, compiled without optimisation. Include this instead of <CLI/CLI.hpp> (a check in the
// build fails on the direct include).
//
// Debian's CLI11 (2.1) is header-only with no precompiled mode: every file that includes it
// generates its code again, and at -O3 that was the largest part of most programs' compile
// time. A command line is parsed once per process, so its speed does not matter: the functions
// defined in CLI11's headers are compiled as if with -O0 (GCC's optimize pragma), the rest of
// the file keeps its level. The standard headers CLI11 uses are included first, outside the
// pragma, so the library code they define keeps the file's level too.

#include <sys/stat.h>
#include <sys/types.h>
#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <exception>
#include <filesystem>
#include <fstream>
#include <functional>
#include <iomanip>
#include <iostream>
#include <iterator>
#include <limits>
#include <locale>
#include <map>
#include <memory>
#include <numeric>
#include <set>
#include <sstream>
#include <stdexcept>
#include <string>
#include <tuple>
#include <type_traits>
#include <utility>
#include <vector>

#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC push_options
#pragma GCC optimize("O0")
#include <CLI/CLI.hpp>
#pragma GCC pop_options
#else
#include <CLI/CLI.hpp>
#endif
