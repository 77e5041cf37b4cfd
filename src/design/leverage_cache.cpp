#include "leverage_cache.hpp"

#include <condition_variable>
#include <mutex>
#include <thread>

namespace robcal {

namespace {
// Below this many candidates a sweep takes well under a thread start-up's worth of time.
constexpr int kParallelCandidates = 2000;

// The widest SIMD packet of doubles this build uses (2 with SSE2, 4 with AVX).
using Packet = Eigen::internal::packet_traits<double>::type;
constexpr int kLanes = Eigen::internal::packet_traits<double>::size;

Eigen::Index padded_columns(Eigen::Index m) {
  return (m + kLanes - 1) / kLanes * kLanes;
}

/// a·vᵀ for two R-row blocks of `columns` contiguous doubles per row (columns a whole number of
/// packets). All R² dot products advance together one packet of columns at a time, so each
/// packet of `a` and `v` is loaded once and the sweep runs at the arithmetic rate.
template <int R>
Eigen::Matrix<double, R, R> block_product(const double* a, const double* v, Eigen::Index columns) {
  Packet acc[R * R];
#pragma GCC unroll 36
  for (int p = 0; p < R * R; ++p) acc[p] = Eigen::internal::pset1<Packet>(0.0);
  for (Eigen::Index c = 0; c < columns; c += kLanes) {
    Packet w[R];
#pragma GCC unroll 6
    for (int l = 0; l < R; ++l) w[l] = Eigen::internal::ploadu<Packet>(v + l * columns + c);
#pragma GCC unroll 6
    for (int i = 0; i < R; ++i) {
      const Packet x = Eigen::internal::ploadu<Packet>(a + i * columns + c);
#pragma GCC unroll 6
      for (int l = 0; l < R; ++l) acc[i * R + l] = Eigen::internal::pmadd(x, w[l], acc[i * R + l]);
    }
  }
  Eigen::Matrix<double, R, R> out;
  for (int i = 0; i < R; ++i)
    for (int l = 0; l < R; ++l) out(i, l) = Eigen::internal::predux(acc[i * R + l]);
  return out;
}

}  // namespace

class SweepWorker {
 public:
  SweepWorker() : thread_([this] { serve(); }) {}
  SweepWorker(const SweepWorker&) = delete;
  SweepWorker& operator=(const SweepWorker&) = delete;
  ~SweepWorker() {
    {
      const std::lock_guard lock(mutex_);
      stop_ = true;
    }
    wake_.notify_one();
    thread_.join();
  }

  /// Runs `task` on the worker while the caller does its own part; returns when it is done.
  template <typename Own>
  void run_beside(const std::function<void()>& task, Own&& own) {
    {
      const std::lock_guard lock(mutex_);
      task_ = &task;
    }
    wake_.notify_one();
    own();
    std::unique_lock lock(mutex_);
    done_.wait(lock, [&] { return task_ == nullptr; });
  }

 private:
  void serve() {
    std::unique_lock lock(mutex_);
    while (true) {
      wake_.wait(lock, [&] { return stop_ || task_ != nullptr; });
      if (stop_) return;
      lock.unlock();
      (*task_)();  // the sweeps are plain arithmetic: nothing to throw
      lock.lock();
      task_ = nullptr;
      done_.notify_one();
    }
  }

  std::mutex mutex_;
  std::condition_variable wake_, done_;
  const std::function<void()>* task_ = nullptr;
  bool stop_ = false;
  std::thread thread_;  // last: started once the members it uses exist
};

template <int R>
LeverageCache<R>::LeverageCache(LeverageCache&&) noexcept = default;

template <int R>
LeverageCache<R>::~LeverageCache() = default;

template <int R>
template <typename F>
void LeverageCache<R>::in_halves(F&& f) const {
  if (n_ < kParallelCandidates) {
    f(0, n_);
    return;
  }
  if (!worker_) worker_ = std::make_unique<SweepWorker>();
  const std::function<void()> second_half = [&] { f(n_ / 2, n_); };
  worker_->run_beside(second_half, [&] { f(0, n_ / 2); });
}

template <int R>
const double* LeverageCache<R>::rows(int i) const {
  return A_.data() + static_cast<Eigen::Index>(i) * R * A_.cols();
}

template <int R>
LeverageCache<R>::LeverageCache(const DesignMatrix& design, double ridge)
    : n_(design.candidates()),
      m_(design.columns()),
      A_(RowMajorMatrix::Zero(design.rows.rows(), padded_columns(design.columns()))),
      G_(static_cast<size_t>(n_)),
      B_(static_cast<size_t>(n_)) {
  A_.leftCols(m_) = design.rows;
  // M⁻¹ = I/ridge: G_i = A_i A_iᵀ / ridge.
  in_halves([&](int begin, int end) {
    for (int k = begin; k < end; ++k)
      G_[static_cast<size_t>(k)] = block_product<R>(rows(k), rows(k), A_.cols()) / ridge;
  });
}

template <int R>
LeverageCache<R>::LeverageCache(const DesignMatrix& design, const Eigen::MatrixXd& inverse)
    : LeverageCache(design, 1.0) {
  recompute(inverse);
}

template <int R>
void LeverageCache<R>::recompute(const Eigen::MatrixXd& inverse) {
  // G_i = A_i (A_i M⁻¹)ᵀ: one product for every candidate's rows, then the blocks.
  RowMajorMatrix AP = RowMajorMatrix::Zero(A_.rows(), A_.cols());
  AP.leftCols(m_).noalias() = A_.leftCols(m_) * inverse;
  in_halves([&](int begin, int end) {
    for (int k = begin; k < end; ++k)
      G_[static_cast<size_t>(k)] = block_product<R>(
          rows(k), AP.data() + static_cast<Eigen::Index>(k) * R * AP.cols(), A_.cols());
  });
}

template <int R>
typename LeverageCache<R>::RowMajorMatrix LeverageCache<R>::padded_transpose(
    const Eigen::MatrixXd& W) const {
  RowMajorMatrix Wt = RowMajorMatrix::Zero(R, A_.cols());
  Wt.leftCols(m_) = W.transpose();
  return Wt;
}

template <int R>
void LeverageCache<R>::project(const Eigen::MatrixXd& W) {
  const RowMajorMatrix Wt = padded_transpose(W);
  in_halves([&](int begin, int end) {
    for (int k = begin; k < end; ++k)
      B_[static_cast<size_t>(k)] = block_product<R>(rows(k), Wt.data(), A_.cols());
  });
}

template <int R>
void LeverageCache<R>::apply(double sign) {
  in_halves([&](int begin, int end) {
    for (int k = begin; k < end; ++k) {
      const Block& b = B_[static_cast<size_t>(k)];
      G_[static_cast<size_t>(k)].noalias() -= sign * (b * b.transpose());
    }
  });
}

template <int R>
void LeverageCache<R>::update(const Eigen::MatrixXd& W, double sign) {
  const RowMajorMatrix Wt = padded_transpose(W);
  in_halves([&](int begin, int end) {
    for (int k = begin; k < end; ++k) {
      const Block b = block_product<R>(rows(k), Wt.data(), A_.cols());
      G_[static_cast<size_t>(k)].noalias() -= sign * (b * b.transpose());
    }
  });
}

template <int R>
void LeverageCache<R>::set_partners(const Eigen::MatrixXd& X) {
  partners_ = RowMajorMatrix::Zero(X.rows(), A_.cols());
  partners_.leftCols(m_) = X;
}

template <int R>
typename LeverageCache<R>::Block LeverageCache<R>::cross(int i, int k) const {
  return block_product<R>(rows(i), partners_.data() + static_cast<Eigen::Index>(k) * R * A_.cols(),
                          A_.cols());
}

template class LeverageCache<1>;
template class LeverageCache<3>;
template class LeverageCache<6>;

}  // namespace robcal
