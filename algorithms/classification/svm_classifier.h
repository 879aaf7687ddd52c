// Seed 004's per-point classifier (Dey et al. 2012, Sect. 3.2.2): a multi-class RBF
// C-SVC with probability outputs from LIBSVM (Debian's libsvm-dev, Chang and Lin),
// trained on standardised features. Never link PCL's `ml` beside it: that library
// carries its own copy of libsvm's symbols.
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <memory>
#include <vector>

#include "synth/param_table.h"

struct svm_model;
struct svm_node;

namespace grapebench {

struct SvmParams {
  // The paper's "radial basis kernel (sigma = 1.0)": read as exp(-|x - y|^2 / (2 sigma^2)),
  // so gamma = 1 / (2 sigma^2) = 0.5 (LIBSVM's exp(-gamma |x - y|^2)); gamma = 1 is the
  // other reading. On standardised features.
  double gamma = 0.5;
  double c = 1;  // LIBSVM's default; the paper does not say
  double cache_mb = 200;
};
const ParamTable<SvmParams>& svm_param_table();

// A trained model: owns LIBSVM's model and the training vectors its support vectors
// point into. Move-only.
class SvmModel {
 public:
  SvmModel();
  SvmModel(SvmModel&&) noexcept;
  SvmModel& operator=(SvmModel&&) noexcept;
  ~SvmModel();
  int classes() const { return classes_; }
  int dims() const { return dims_; }
  int support_vectors() const;
  const svm_model* get() const { return model_.get(); }

 private:
  friend SvmModel train_svm(const Eigen::MatrixXd&, const std::vector<int>&, int, const SvmParams&, std::uint64_t);
  struct Free {
    void operator()(svm_model* m) const;
  };
  std::unique_ptr<svm_model, Free> model_;
  std::vector<svm_node> nodes_;
  int classes_ = 0;
  int dims_ = 0;
};

// x: M x D training features; y: M class indices in [0, classes). LIBSVM's probability
// fit draws from the C library's rand(): training holds a process-wide lock and seeds
// it with `seed`, so a model is the same at any thread count. Throws InputError on
// fewer than two classes present, sizes that differ or non-finite features.
SvmModel train_svm(const Eigen::MatrixXd& x, const std::vector<int>& y, int classes, const SvmParams& p,
                   std::uint64_t seed);

// N x classes probabilities (rows sum to 1; a class absent from training gets 0), in
// parallel over rows (the model is read-only).
Eigen::MatrixXd svm_probabilities(const SvmModel& model, const Eigen::MatrixXd& x);

}  // namespace grapebench
