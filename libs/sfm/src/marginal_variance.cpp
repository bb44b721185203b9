#include "marginal_variance.h"

#include <Eigen/Dense>
#include <Eigen/SparseCholesky>
#include <cmath>
#include <unordered_map>

namespace omnisfm::sfm {
namespace {

using RowMajorMatrix = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;

// The information of the blocks left once the points are eliminated, symmetric, by blocks. Dense
// when small enough (short sequences, where most frames share points and it is dense anyway);
// block-sparse otherwise (long drives, where it is banded).
class ReducedInformation {
 public:
  ReducedInformation(std::vector<int> offsets, std::vector<int> sizes, int dimension)
      : offsets_(std::move(offsets)), sizes_(std::move(sizes)), dimension_(dimension),
        dense_(dimension <= kMaxDense) {
    if (dense_) matrix_.setZero(dimension, dimension);
  }

  // H_ab += block (and H_ba += its transpose when a != b).
  void add(int a, int b, const Eigen::MatrixXd& block) {
    if (dense_) {
      matrix_.block(offsets_[a], offsets_[b], sizes_[a], sizes_[b]) += block;
      if (a != b)
        matrix_.block(offsets_[b], offsets_[a], sizes_[b], sizes_[a]) += block.transpose();
      return;
    }
    if (a > b) return add(b, a, block.transpose());
    Eigen::MatrixXd& stored = blocks_[static_cast<long long>(a) * offsets_.size() + b];
    if (stored.size() == 0) stored.setZero(sizes_[a], sizes_[b]);
    stored += block;
  }

  // H -= G^T G for one eliminated point, G = V^(-1/2) W: `columns` (block, first column in G)
  // say where each block's columns are. Dense, G's rows are kept and subtracted at once
  // (one matrix product, where block by block it is the cost of the whole solve).
  void subtract_point(const std::vector<std::pair<int, int>>& columns,
                      const Eigen::Matrix<double, 3, Eigen::Dynamic>& G) {
    if (dense_) {
      if (eliminated_rows_ + 3 > eliminated_.rows())
        eliminated_.conservativeResize(std::max<Eigen::Index>(64, 2 * eliminated_.rows()),
                                       dimension_);
      eliminated_.middleRows(eliminated_rows_, 3).setZero();
      for (const auto& [block, column] : columns)
        eliminated_.block(eliminated_rows_, offsets_[block], 3, sizes_[block]) =
            G.middleCols(column, sizes_[block]);
      eliminated_rows_ += 3;
      return;
    }
    for (size_t i = 0; i < columns.size(); ++i)
      for (size_t j = i; j < columns.size(); ++j) {
        const auto [a, column_a] = columns[i];
        const auto [b, column_b] = columns[j];
        add(a, b,
            -(G.middleCols(column_a, sizes_[a]).transpose() * G.middleCols(column_b, sizes_[b])));
      }
  }

  // (H^-1)_ii; INFINITY when H is not positive definite.
  double inverse_entry(int index) const {
    Eigen::VectorXd unit = Eigen::VectorXd::Zero(dimension_);
    unit[index] = 1;
    if (dense_) {
      Eigen::MatrixXd matrix = matrix_;
      matrix.selfadjointView<Eigen::Lower>().rankUpdate(
          eliminated_.topRows(eliminated_rows_).transpose(), -1);
      const Eigen::LLT<Eigen::MatrixXd> factor(matrix);
      if (factor.info() != Eigen::Success) return INFINITY;
      return factor.solve(unit)[index];
    }
    std::vector<Eigen::Triplet<double>> entries;
    const long long count = static_cast<long long>(offsets_.size());
    for (const auto& [key, block] : blocks_) {
      const int a = static_cast<int>(key / count), b = static_cast<int>(key % count);
      for (int i = 0; i < block.rows(); ++i)
        for (int j = 0; j < block.cols(); ++j) {
          // The lower triangle, as the factorisation reads it.
          if (a == b && j > i) continue;
          if (a == b) entries.emplace_back(offsets_[a] + i, offsets_[b] + j, block(i, j));
          else entries.emplace_back(offsets_[b] + j, offsets_[a] + i, block(i, j));
        }
    }
    Eigen::SparseMatrix<double> matrix(dimension_, dimension_);
    matrix.setFromTriplets(entries.begin(), entries.end());
    const Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>, Eigen::Lower> factor(matrix);
    if (factor.info() != Eigen::Success || !(factor.vectorD().minCoeff() > 0)) return INFINITY;
    return factor.solve(unit)[index];
  }

 private:
  static constexpr int kMaxDense = 1200;
  std::vector<int> offsets_, sizes_;
  int dimension_;
  bool dense_;
  Eigen::MatrixXd matrix_;
  Eigen::MatrixXd eliminated_;  // the eliminated points' G, stacked (dense only)
  Eigen::Index eliminated_rows_ = 0;
  std::unordered_map<long long, Eigen::MatrixXd> blocks_;
};

// What one point's residuals say: V = J_p^T J_p and, per other block b, W_b = J_p^T J_b.
struct PointInformation {
  Eigen::Matrix3d V = Eigen::Matrix3d::Zero();
  std::unordered_map<int, Eigen::Matrix<double, 3, Eigen::Dynamic>> W;
};

}  // namespace

double marginal_variance(ceres::Problem* problem, double* scalar,
                         const std::vector<double*>& points) {
  std::unordered_map<const double*, int> point_index, block_index;
  for (double* p : points)
    if (problem->HasParameterBlock(p) && !problem->IsParameterBlockConstant(p))
      point_index.emplace(p, static_cast<int>(point_index.size()));
  std::vector<double*> blocks;
  problem->GetParameterBlocks(&blocks);
  std::vector<int> offsets, sizes;
  int dimension = 0;
  for (double* b : blocks) {
    if (point_index.count(b) || problem->IsParameterBlockConstant(b)) continue;
    block_index.emplace(b, static_cast<int>(offsets.size()));
    offsets.push_back(dimension);
    sizes.push_back(problem->ParameterBlockTangentSize(b));
    dimension += sizes.back();
  }
  const auto found = block_index.find(scalar);
  if (found == block_index.end() || sizes[found->second] != 1) return NAN;

  ReducedInformation information(offsets, sizes, dimension);
  std::vector<PointInformation> point_information(point_index.size());
  std::vector<ceres::ResidualBlockId> residuals;
  problem->GetResidualBlocks(&residuals);
  std::vector<double*> parameters;
  std::vector<RowMajorMatrix> jacobians;
  std::vector<double*> jacobian_pointers;
  std::vector<double> values;
  for (const ceres::ResidualBlockId id : residuals) {
    problem->GetParameterBlocksForResidualBlock(id, &parameters);
    const int rows = problem->GetCostFunctionForResidualBlock(id)->num_residuals();
    jacobians.resize(parameters.size());
    jacobian_pointers.assign(parameters.size(), nullptr);
    int point = -1, point_k = -1;
    std::vector<std::pair<int, int>> others;  // (block index, k)
    for (size_t k = 0; k < parameters.size(); ++k) {
      if (problem->IsParameterBlockConstant(parameters[k])) continue;
      jacobians[k].resize(rows, problem->ParameterBlockTangentSize(parameters[k]));
      jacobian_pointers[k] = jacobians[k].data();
      if (const auto p = point_index.find(parameters[k]); p != point_index.end()) {
        point = p->second;
        point_k = static_cast<int>(k);
      } else {
        others.emplace_back(block_index.at(parameters[k]), static_cast<int>(k));
      }
    }
    values.resize(rows);
    double cost = 0;
    if (!problem->EvaluateResidualBlock(id, true, &cost, values.data(), jacobian_pointers.data()))
      return INFINITY;
    for (size_t i = 0; i < others.size(); ++i)
      for (size_t j = i; j < others.size(); ++j)
        information.add(others[i].first, others[j].first,
                        jacobians[others[i].second].transpose() * jacobians[others[j].second]);
    if (point < 0) continue;
    PointInformation& pi = point_information[point];
    const RowMajorMatrix& J_point = jacobians[point_k];
    pi.V += J_point.transpose() * J_point;
    for (const auto& [block, k] : others) {
      auto& W = pi.W[block];
      if (W.cols() == 0) W.setZero(3, sizes[block]);
      W += J_point.transpose() * jacobians[k];
    }
  }

  // Each point eliminated: H -= W^T V^-1 W. A point its residuals do not fix in some direction
  // (seen from one place) leaves that direction out (V's pseudo-inverse): nothing else sees it.
  for (const PointInformation& pi : point_information) {
    if (pi.W.empty()) continue;
    const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eigen(pi.V);
    const Eigen::Vector3d lambda = eigen.eigenvalues();
    Eigen::Matrix3d root_inverse = Eigen::Matrix3d::Zero();  // R with R^T R = V^-1
    for (int i = 0; i < 3; ++i)
      if (lambda[i] > 1e-12 * lambda[2])
        root_inverse.row(i) = eigen.eigenvectors().col(i).transpose() / std::sqrt(lambda[i]);
    std::vector<std::pair<int, int>> columns;  // (block, first column in the stacked W)
    int width = 0;
    for (const auto& [block, W] : pi.W) {
      columns.emplace_back(block, width);
      width += static_cast<int>(W.cols());
    }
    Eigen::Matrix<double, 3, Eigen::Dynamic> stacked(3, width);
    for (const auto& [block, column] : columns)
      stacked.middleCols(column, sizes[block]) = root_inverse * pi.W.at(block);
    information.subtract_point(columns, stacked);
  }
  return information.inverse_entry(offsets[found->second]);
}

}  // namespace omnisfm::sfm
