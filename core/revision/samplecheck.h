/***************************************************************************
  samplecheck.h - one place along a map road, checked in both images
  -------------------------------------------------------------------------
  The decisions maprevision.h makes sample by sample: a band on the
  mapped course in both images (confirmed), the bands off it in the first
  image that the second confirms (moved candidates), which of them a moved
  stretch settles on, which samples a neighbour continues, which gaps a
  road runs on through (a junction), and each sample's status as the
  majority of its neighbours'.
 ***************************************************************************/
#ifndef GEOSTATION_REVISION_SAMPLECHECK_H
#define GEOSTATION_REVISION_SAMPLECHECK_H

#include <functional>
#include <optional>
#include <vector>

#include <Eigen/Core>

#include "extraction/crossprofile.h"
#include "extraction/greytiles.h"
#include "extraction/pairmapping.h"
#include "geometry/projection.h"
#include "revision/maprevision.h"

namespace geostation::revision
{

  //! One place along a map road, as checked.
  struct Sample
  {
    Eigen::Vector3d ground = Eigen::Vector3d::Zero(); //!< on the mapped course, at the terrain
    Eigen::Vector2d inA = Eigen::Vector2d::Zero(), inB = Eigen::Vector2d::Zero();
    RevisionStatus status = RevisionStatus::Outside;
    Eigen::Vector2d foundA = Eigen::Vector2d::Zero(), foundB = Eigen::Vector2d::Zero(); //!< the band's centre, confirmed or moved
    double shiftM = 0.0;
    double offsetPx = 0.0, widthPx = 0.0; //!< confirmed or moved: the band's offset across the course in A and its width there
    bool occluded = false; //!< a surface model hides it from a camera (MapRevisionOptions::surface)
    //! Moved: every band off the course in A that B confirms (offset across the course in A, px; where; how far)
    struct Candidate
    {
      double offsetPx, widthPx;
      Eigen::Vector2d inA, inB;
      double shiftM;
    };
    std::vector<Candidate> candidates;
  };

  //! What the check needs of the pair.
  struct PairView
  {
    const GreyTiles &greyA, &greyB;
    const OrientedPairMapping &mapping;
    LineObjectOptions object;
    double groundPixelM = 0.0, tolerancePx = 0.0, shiftMaxPx = 0.0;
    double terrainSigmaM = 0.0; //!< of a height taken from the terrain
    double longAlongPx = 0.0;   //!< the long profiles' averaging along the course, either side (check()); up to 1.5: none
  };

  //! The pixel of `ground` in `image`, and whether it lies more than `marginPx` inside the frame.
  bool inFrame( const OrientedImage &image, const Eigen::Vector3d &ground, Eigen::Vector2d &pixel, double marginPx );

  /**
   * Whether the ray from `image`'s projection centre to `ground` meets
   * `surface` more than `clearanceM` above `ground` (a building, a tree, a
   * hill in between).
   */
  bool hiddenFrom( const OrientedImage &image, const Eigen::Vector3d &ground,
                   const std::function<std::optional<Eigen::Vector3d>( const Ray & )> &surface, double clearanceM );

  /**
   * The bands across `along` at `at` within `searchPx` of it, nearest
   * first (offsets along the normal of `along`), on the profile averaged
   * over `alongHalfPx` either side along `along`.
   */
  std::vector<CrossSection> bandsNear( const GreyTiles &grey, const Eigen::Vector2d &at, const Eigen::Vector2d &along, const LineObjectOptions &object, double searchPx,
                                       double alongHalfPx = 1.5, bool oneSided = false );

  //! The course's direction at sample `i` in the first image (`inA`) or the second, from its neighbours.
  Eigen::Vector2d directionAt( const std::vector<Sample> &samples, size_t i, bool inA );

  /**
   * One sample's status: a band on the mapped course in both images
   * (confirmed); else the bands within the shift allowed in A whose ground
   * point shows a band in B (moved, the nearest for now); else not found.
   */
  void check( Sample &s, const Eigen::Vector2d &alongA, const Eigen::Vector2d &alongB, const PairView &pair );

  //! The moved samples settled on the band their neighbours share (see samplecheck.cpp).
  void settleShifts( std::vector<Sample> &samples );

  //! Confirmed and moved samples not continued by a neighbour become not found (see samplecheck.cpp).
  void requireContinuity( std::vector<Sample> &samples );

  /**
   * A road runs on through a junction: where another road joins, its band
   * opens on that side and the profiles across the course show none (nor
   * a moved road: a band beside it, a verge or a strip of field, may stand
   * out). A gap between two confirmed samples whose bands agree (offsets
   * within 2 px, widths within 40 %), or between a confirmed sample and
   * the road's end (map roads end at junctions), no longer in the first
   * image than twice the road's width and the tolerance either side (a
   * junction's mouth, not a stretch of field beside a road lost), is
   * confirmed at each sample where
   * both images show a band open on one side at that offset and width:
   * uniform inside, one side standing out by the minimum contrast.
   */
  void confirmThroughJunctions( std::vector<Sample> &samples, const PairView &pair );

  //! Each sample's status replaced by the majority within `half` samples either side (ties keep their own).
  std::vector<RevisionStatus> majorityStatus( const std::vector<Sample> &samples, int half );

} // namespace geostation::revision

#endif // GEOSTATION_REVISION_SAMPLECHECK_H
