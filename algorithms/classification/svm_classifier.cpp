#include "algorithms/classification/svm_classifier.h"

#include <libsvm/svm.h>
#include <tbb/parallel_for.h>

#include <cstdlib>
#include <mutex>
#include <string>

#include "synth/config.h"

namespace grapebench {

const ParamTable<SvmParams>& svm_param_table() {
  using P = SvmParams;
  static const ParamTable<P> table =
      ParamTable<P>()
          .real("gamma", "-", &P::gamma, 1e-6, 1e6,
                "RBF exp(-gamma |x - y|^2) on standardised features; 0.5 = the paper's sigma 1.0 read as "
                "1 / (2 sigma^2) (seed 004 Sect. 4.2)")
          .real("c", "-", &P::c, 1e-6, 1e6, "C-SVC penalty (not stated in seed 004; LIBSVM's default 1)")
          .real("cache_mb", "MB", &P::cache_mb, 1, 100000, "LIBSVM's kernel cache");
  return table;
}

void SvmModel::Free::operator()(svm_model* m) const {
  if (m) svm_free_and_destroy_model(&m);
}
SvmModel::SvmModel() = default;
SvmModel::SvmModel(SvmModel&&) noexcept = default;
SvmModel& SvmModel::operator=(SvmModel&&) noexcept = default;
SvmModel::~SvmModel() = default;
int SvmModel::support_vectors() const { return model_ ? svm_get_nr_sv(model_.get()) : 0; }

namespace {

std::mutex& libsvm_lock() {
  static std::mutex m;
  return m;
}
void quiet(const char*) {}

// Row i of x as LIBSVM's sparse vector (every feature written, index from 1, -1 ends).
void write_row(const Eigen::MatrixXd& x, Eigen::Index i, svm_node* out) {
  for (Eigen::Index d = 0; d < x.cols(); ++d) out[d] = {static_cast<int>(d + 1), x(i, d)};
  out[x.cols()] = {-1, 0};
}

}  // namespace

SvmModel train_svm(const Eigen::MatrixXd& x, const std::vector<int>& y, int classes, const SvmParams& p,
                   std::uint64_t seed) {
  if (static_cast<std::size_t>(x.rows()) != y.size())
    throw InputError("train_svm: " + std::to_string(x.rows()) + " feature rows for " + std::to_string(y.size()) +
                     " labels");
  if (!x.allFinite()) throw InputError("train_svm: a training feature is not finite");
  std::vector<int> seen(static_cast<std::size_t>(classes), 0);
  for (int c : y) {
    if (c < 0 || c >= classes) throw InputError("train_svm: label " + std::to_string(c) + " outside [0, classes)");
    seen[static_cast<std::size_t>(c)] = 1;
  }
  int present = 0;
  for (int s : seen) present += s;
  if (present < 2) throw InputError("train_svm: training needs points of at least two classes");

  SvmModel m;
  m.classes_ = classes;
  m.dims_ = static_cast<int>(x.cols());
  const std::size_t stride = static_cast<std::size_t>(x.cols()) + 1;
  m.nodes_.resize(stride * static_cast<std::size_t>(x.rows()));
  std::vector<svm_node*> rows(static_cast<std::size_t>(x.rows()));
  std::vector<double> labels(y.begin(), y.end());
  for (Eigen::Index i = 0; i < x.rows(); ++i) {
    rows[static_cast<std::size_t>(i)] = m.nodes_.data() + stride * static_cast<std::size_t>(i);
    write_row(x, i, rows[static_cast<std::size_t>(i)]);
  }
  svm_problem prob{static_cast<int>(x.rows()), labels.data(), rows.data()};
  svm_parameter param{};
  param.svm_type = C_SVC;
  param.kernel_type = RBF;
  param.gamma = p.gamma;
  param.cache_size = p.cache_mb;
  param.eps = 1e-3;
  param.C = p.c;
  param.shrinking = 1;
  param.probability = 1;
  if (const char* why = svm_check_parameter(&prob, &param)) throw InputError(std::string("train_svm: ") + why);
  const std::lock_guard<std::mutex> lock(libsvm_lock());
  svm_set_print_string_function(&quiet);
  std::srand(static_cast<unsigned>(seed ^ (seed >> 32)));  // the probability fit's folds
  m.model_.reset(svm_train(&prob, &param));
  return m;
}

Eigen::MatrixXd svm_probabilities(const SvmModel& model, const Eigen::MatrixXd& x) {
  if (!model.get()) throw InputError("svm_probabilities: no trained model");
  if (x.cols() != model.dims()) throw InputError("svm_probabilities: features of the wrong width");
  const int k = svm_get_nr_class(model.get());
  std::vector<int> label(static_cast<std::size_t>(k));
  svm_get_labels(model.get(), label.data());
  Eigen::MatrixXd out = Eigen::MatrixXd::Zero(x.rows(), model.classes());
  tbb::parallel_for(tbb::blocked_range<Eigen::Index>(0, x.rows(), 64), [&](const tbb::blocked_range<Eigen::Index>& r) {
    std::vector<svm_node> row(static_cast<std::size_t>(x.cols()) + 1);
    std::vector<double> prob(static_cast<std::size_t>(k));
    for (Eigen::Index i = r.begin(); i != r.end(); ++i) {
      write_row(x, i, row.data());
      svm_predict_probability(model.get(), row.data(), prob.data());
      for (int c = 0; c < k; ++c) out(i, label[static_cast<std::size_t>(c)]) = prob[static_cast<std::size_t>(c)];
    }
  });
  return out;
}

}  // namespace grapebench
