// statistics_json: the statistics module (statistics.h) on cases read from stdin, one result per
// line as JSON, for tests/scripts/test_statistics_equal.py to compare with python/grainlift/
// stats.py. Input, one case per line, numbers as Python's repr writes them:
//   block_mean B N x_1 ... x_N
//   pooled_mean N E m_1 ... m_N [e_1 ... e_N if E is 1]
//   richardson h_1 h_2 h_3 f_1 f_2 f_3
// Output: {"mean": ..., ...} with 17 significant digits, null for NaN.
#include <cmath>
#include <cstdio>
#include <iostream>
#include <sstream>
#include <string>
#include <vector>

#include "grainlift/shared/statistics/statistics.h"

namespace {

std::string num(double x) {
  if (!std::isfinite(x)) return "null";
  char buf[40];
  std::snprintf(buf, sizeof buf, "%.17g", x);
  return buf;
}

std::vector<double> read(std::istringstream& in, std::size_t n) {
  std::vector<double> v(n);
  for (auto& x : v) in >> x;
  return v;
}

}  // namespace

int main() {
  std::string line;
  while (std::getline(std::cin, line)) {
    std::istringstream in(line);
    std::string kind;
    if (!(in >> kind)) continue;
    if (kind == "block_mean") {
      std::size_t B = 0, n = 0;
      in >> B >> n;
      const grainlift::BlockMean m = grainlift::block_mean(read(in, n), B);
      std::cout << "{\"mean\": " << num(m.mean) << ", \"stderr\": " << num(m.stderr_)
                << ", \"lag1\": " << num(m.lag1) << ", \"stderr_corrected\": "
                << num(m.stderr_corrected) << ", \"blocks\": " << m.blocks
                << ", \"samples\": " << m.samples << "}\n";
    } else if (kind == "pooled_mean") {
      std::size_t n = 0;
      int with_errors = 0;
      in >> n >> with_errors;
      const std::vector<double> means = read(in, n);
      const std::vector<double> errors = with_errors ? read(in, n) : std::vector<double>{};
      const grainlift::PooledMean p = grainlift::pooled_mean(means, errors);
      std::cout << "{\"mean\": " << num(p.mean) << ", \"error\": " << num(p.error)
                << ", \"between\": " << num(p.between) << ", \"within\": " << num(p.within)
                << ", \"beds\": " << p.beds << "}\n";
    } else if (kind == "richardson") {
      const std::vector<double> h = read(in, 3), f = read(in, 3);
      const grainlift::Richardson r = grainlift::richardson(h, f);
      std::cout << "{\"order\": " << num(r.order) << ", \"limit\": " << num(r.limit)
                << ", \"error\": " << num(r.error)
                << ", \"accepted\": " << (r.accepted ? "true" : "false") << "}\n";
    } else {
      std::cerr << "statistics_json: unknown case '" << kind << "'\n";
      return 2;
    }
    if (!in) {
      std::cerr << "statistics_json: malformed line: " << line << "\n";
      return 2;
    }
  }
  return 0;
}
