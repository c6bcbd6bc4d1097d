#pragma once

#include <cstddef>
#include <vector>

#include <Eigen/Core>

namespace trav::common {

/// A matrix whose storage keeps its capacity between uses: `Resize` returns a view of the requested
/// shape and allocates only when it needs more elements than ever before. A loop that reuses one
/// allocates nothing once its sizes have been seen (DESIGN.md: hot loops allocate nothing); an
/// Eigen dynamic matrix frees and reallocates its storage on every change of size. The contents
/// after `Resize` are unspecified.
template <typename Scalar, int Rows = Eigen::Dynamic, int Cols = Eigen::Dynamic>
class ScratchMatrix {
 public:
  using Matrix = Eigen::Matrix<Scalar, Rows, Cols>;
  using View = Eigen::Map<Matrix, Eigen::Aligned16>;
  using ConstView = Eigen::Map<const Matrix, Eigen::Aligned16>;

  /// A view of `rows` x `cols` (each fixed dimension must equal its compile-time size).
  View Resize(Eigen::Index rows, Eigen::Index cols) {
    const auto size = static_cast<std::size_t>(rows * cols);
    if (size > data_.size()) data_.resize(size);
    rows_ = rows;
    cols_ = cols;
    return view();
  }
  /// A view of a vector of `size` entries (one of the dimensions fixed at 1).
  View Resize(Eigen::Index size) {
    static_assert(Rows == 1 || Cols == 1, "Resize(size) is for vectors");
    return Rows == 1 ? Resize(1, size) : Resize(size, 1);
  }

  View view() { return View(data_.data(), rows_, cols_); }
  ConstView view() const { return ConstView(data_.data(), rows_, cols_); }
  ConstView const_view() const { return view(); }
  Eigen::Index rows() const { return rows_; }
  Eigen::Index cols() const { return cols_; }

 private:
  std::vector<Scalar, Eigen::aligned_allocator<Scalar>> data_;
  Eigen::Index rows_{Rows == Eigen::Dynamic ? 0 : Rows};
  Eigen::Index cols_{Cols == Eigen::Dynamic ? 0 : Cols};
};

}  // namespace trav::common
