// policy_probe MODEL.pt INPUT: loads an exported policy with torch::jit::load (nothing of rlt
// linked) and prints its deterministic actions, so tests can check an export from a fresh process.
//
// INPUT (whitespace separated):
//   B M N                     rows, mask width (0 = call without a mask), observation count
//   N lines: R d1 .. dR       shape of each observation without the batch dimension
//   B rows of floats          each row the observations flattened and concatenated
//   if M > 0: B rows of M     mask values (1 = allowed)
// Output: "spec_json <json>", "format_version <n>", then per row "c1 .. cC | d1 .. dK".
#include <torch/script.h>

#include <cstdio>
#include <fstream>
#include <iostream>
#include <vector>

int main(int argc, char** argv) {
  if (argc != 3) {
    std::cerr << "usage: policy_probe MODEL.pt INPUT\n";
    return 2;
  }
  std::ifstream in(argv[2]);
  int64_t rows = 0, mask_width = 0, count = 0;
  if (!(in >> rows >> mask_width >> count)) {
    std::cerr << "bad input header\n";
    return 2;
  }
  std::vector<std::vector<int64_t>> shapes(count);
  std::vector<int64_t> sizes(count, 1);
  int64_t width = 0;
  for (int64_t i = 0; i < count; ++i) {
    int64_t rank = 0;
    in >> rank;
    shapes[i].push_back(rows);
    for (int64_t d = 0; d < rank; ++d) {
      int64_t n = 0;
      in >> n;
      shapes[i].push_back(n);
      sizes[i] *= n;
    }
    width += sizes[i];
  }
  auto flat = torch::empty({rows, width});
  for (int64_t r = 0; r < rows; ++r)
    for (int64_t c = 0; c < width; ++c) {
      float v = 0;
      in >> v;
      flat[r][c] = v;
    }
  torch::Tensor mask;
  if (mask_width > 0) {
    mask = torch::empty({rows, mask_width});
    for (int64_t r = 0; r < rows; ++r)
      for (int64_t c = 0; c < mask_width; ++c) {
        float v = 0;
        in >> v;
        mask[r][c] = v;
      }
  }
  if (!in) {
    std::cerr << "input ended early\n";
    return 2;
  }
  // split the rows into the observation tensors
  c10::List<torch::Tensor> observations;
  int64_t offset = 0;
  for (int64_t i = 0; i < count; ++i) {
    observations.push_back(flat.narrow(1, offset, sizes[i]).reshape(shapes[i]).contiguous());
    offset += sizes[i];
  }

  torch::jit::Module module = torch::jit::load(argv[1]);
  module.eval();
  std::vector<torch::jit::IValue> inputs{observations};
  if (mask.defined()) inputs.push_back(mask);
  auto result = module.forward(inputs).toTuple();
  auto continuous = result->elements()[0].toTensor().contiguous();
  auto discrete = result->elements()[1].toTensor().contiguous();

  std::cout << "spec_json " << module.attr("spec_json").toStringRef() << "\n";
  std::cout << "format_version " << module.attr("format_version").toInt() << "\n";
  for (int64_t r = 0; r < rows; ++r) {
    for (int64_t c = 0; c < continuous.size(1); ++c)
      std::printf("%.9g ", continuous[r][c].item<float>());
    std::printf("|");
    for (int64_t k = 0; k < discrete.size(1); ++k)
      std::printf(" %lld", static_cast<long long>(discrete[r][k].item<int64_t>()));
    std::printf("\n");
  }
  std::fflush(stdout);
  return 0;
}
