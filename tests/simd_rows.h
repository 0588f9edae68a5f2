// Rows of floats for testing a core SIMD twin against its scalar function: the tests fill input
// rows and the scalar results, a per-target kernel reads the inputs and writes output rows through
// row pointers, and every target's outputs must equal the scalar ones bit for bit (docs/design.md §11).
#pragma once

#include <cstddef>
#include <random>
#include <vector>

#include <catch2/catch.hpp>
#include <glm/glm.hpp>

#include "tests/test_support.h"

namespace ssgi::test {

// `rows` rows of `count` floats, and pointers to them as a kernel takes them.
struct SimdRows {
  std::vector<std::vector<float>> values;
  std::vector<const float*> in;
  std::vector<float*> out;

  SimdRows(size_t rows, size_t count) : values(rows, std::vector<float>(count)) {
    for (std::vector<float>& row : values) {
      in.push_back(row.data());
      out.push_back(row.data());
    }
  }
  // v's components into rows `row`, `row` + 1, `row` + 2 at i.
  void Set3(size_t row, size_t i, glm::vec3 v) {
    for (int c = 0; c < 3; ++c) values[row + size_t(c)][i] = v[c];
  }
};

// A random unit vector, uniform over the sphere: inputs for the twins' tests.
inline glm::vec3 RandomUnitVector(std::mt19937& rng) {
  std::normal_distribution<float> normal;
  return glm::normalize(glm::vec3(normal(rng), normal(rng), normal(rng)));
}

// Runs kernel(outputRows) on every compiled and supported target and checks the first `count`
// values of every row against `expected`.
template <class Kernel>
void CheckEveryTarget(const SimdRows& expected, size_t count, Kernel&& kernel) {
  SimdRows actual(expected.values.size(), expected.values[0].size());
  const size_t targets = ForEachSimdTarget([&](const char* target) {
    kernel(actual.out.data());
    for (size_t row = 0; row < expected.values.size(); ++row) {
      const size_t first = FirstDifferentBits(actual.values[row].data(), expected.values[row].data(), count);
      CAPTURE(target, count, row, first);
      CHECK(first == count);
    }
  });
  CHECK(targets >= 1);
}

}  // namespace ssgi::test
