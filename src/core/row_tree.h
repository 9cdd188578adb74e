// A nanoflann k-d tree over the rows of an #N×3 matrix (points, mesh vertices), all of them or a
// chosen subset: the one adaptor every stage uses for nearest-point searches.
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <nanoflann.hpp>
#include <vector>

namespace s2p {

// nanoflann's dataset view. Both pointers must outlive the tree; `rows` null: every row of V.
// The tree's indices are positions in `rows` (or rows of V when null).
struct RowCloud {
  const Eigen::MatrixX3d* V = nullptr;
  const std::vector<int>* rows = nullptr;
  size_t kdtree_get_point_count() const {
    return rows ? rows->size() : static_cast<size_t>(V->rows());
  }
  double kdtree_get_pt(size_t i, size_t d) const {
    const Eigen::Index r = rows ? (*rows)[i] : static_cast<Eigen::Index>(i);
    return (*V)(r, static_cast<Eigen::Index>(d));
  }
  template <class Box>
  bool kdtree_get_bbox(Box&) const {
    return false;  // nanoflann computes the bounding box itself
  }
};

using RowTree = nanoflann::KDTreeSingleIndexAdaptor<nanoflann::L2_Simple_Adaptor<double, RowCloud>,
                                                    RowCloud, 3, std::uint32_t>;

}  // namespace s2p
