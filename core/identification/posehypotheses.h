/***************************************************************************
  posehypotheses.h - camera poses from triangles of control and candidates
  -------------------------------------------------------------------------
  The hypothesis stage of the control identification
  (controlidentification.h): a control point with two of its nearest
  neighbours on the ground, paired with a candidate and two of its nearest
  candidates in the image, gives up to four poses (P3P); each pose is
  scored by the control points it projects onto candidates, every match
  weighted by how unlikely it is by chance (-log of the chance of landing
  on that candidate, from the candidates around it). The best poses are
  kept for verification.

  A pairing is tried only when it keeps the triangle's sense of rotation (a
  camera above a near-horizontal triangle cannot mirror it) and the scales
  of its three sides agree within the foreshortening allowed.
 ***************************************************************************/
#ifndef GEOSTATION_IDENTIFICATION_POSEHYPOTHESES_H
#define GEOSTATION_IDENTIFICATION_POSEHYPOTHESES_H

#include <array>
#include <memory>
#include <utility>
#include <vector>

#include <Eigen/Core>

#include "identification/threepointpose.h"

namespace geostation
{

  //! Control index -> candidate index, sorted by control index.
  using ControlPairs = std::vector<std::pair<int, int>>;

  //! One-to-one pairs from (distance, control, candidate) proposals, nearest first.
  ControlPairs matchOneToOne( std::vector<std::tuple<double, int, int>> proposals );

  struct PoseHypothesisOptions
  {
    int neighboursOnGround = 4;
    int neighboursInImage = 6;
    double maxForeshortening = 5.0;
    double tolerance = 0.005;       //!< ideal units: a control projected this close to a candidate matches
    double minSideIdeal = 0.002;    //!< shortest triangle side in the image, ideal units
    size_t kept = 384;              //!< best poses kept
  };

  struct PoseHypothesis
  {
    double score = 0.0;
    ThreePointPose pose;
  };

  class PoseHypotheses
  {
    public:
      /**
       * `local`: control in a local frame (metres); `ideal`: candidates as
       * ideal normalised coordinates; `worth`: each candidate's match value;
       * `imageCandidates`: the candidates triangles are formed from;
       * `allowed` (empty, or one list per control point): with an approximate
       * orientation, the candidates each control point may pair with - then
       * any of them, not only the neighbours, forms triangles.
       */
      PoseHypotheses( const std::vector<Eigen::Vector3d> &local, const std::vector<Eigen::Vector2d> &ideal, const std::vector<double> &worth,
                      const std::vector<int> &groundControl, const std::vector<int> &imageCandidates, const std::vector<std::vector<int>> &allowed,
                      const PoseHypothesisOptions &options );
      ~PoseHypotheses();

      //! Tries every triangle whose first point is paired with `candidate`.
      void addFrom( int candidate );

      //! The kept poses, best first.
      std::vector<PoseHypothesis> best() const;

      //! The pairs a pose makes (within the tolerance, one to one).
      ControlPairs pairsOf( const ThreePointPose &pose ) const;

      long triangles() const { return mTriangleCount; }
      long poses() const { return mPoseCount; }

    private:
      class Grid;
      const std::vector<Eigen::Vector3d> &mLocal;
      const std::vector<Eigen::Vector2d> &mIdeal;
      const std::vector<double> &mWorth;
      const std::vector<std::vector<int>> &mAllowed;
      PoseHypothesisOptions mOptions;
      std::unique_ptr<Grid> mGrid;
      std::vector<std::array<int, 3>> mTriangles;
      std::vector<std::vector<int>> mImageNeighbours;
      std::vector<PoseHypothesis> mHeap; //!< a min-heap on the score
      long mTriangleCount = 0, mPoseCount = 0;
  };

} // namespace geostation

#endif // GEOSTATION_IDENTIFICATION_POSEHYPOTHESES_H
