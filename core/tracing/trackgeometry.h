/***************************************************************************
  trackgeometry.h - a road line and the van's track (thesis §6.5.3)
  -------------------------------------------------------------------------
  Where a traced line goes on beyond what was traced - straight on along
  its own last stretch, or parallel to the van's track (road lines run
  with the road) - and the road surface under the track, for the road
  plane of each station and the check of every vertex. Plan distances in
  metres, heights in the block CRS.
 ***************************************************************************/
#ifndef GEOSTATION_TRACING_TRACKGEOMETRY_H
#define GEOSTATION_TRACING_TRACKGEOMETRY_H

#include <optional>
#include <vector>

#include <Eigen/Core>

namespace geostation
{

  /**
   * The line continued beyond its last vertex every `step` metres up to
   * `length`: a parabola fitted in plan to its last 30 m (so a road curve
   * keeps bending, and the direction comes from more than one dash), with
   * the grade of that stretch in height.
   */
  std::vector<Eigen::Vector3d> continuation( const std::vector<Eigen::Vector3d> &vertices, const Eigen::Vector3d &direction, double length, double step );

  /**
   * The line continued parallel to the van's trajectory (the reference
   * camera's path through the run): the last vertex keeps its offset from
   * the trajectory and follows its curves and grade, every `step` metres up
   * to `length`, in the run's direction `stepSign` (+1 / -1). With
   * `leftOffsetM`, the continuation keeps that offset instead of the last
   * vertex's own (see recentTrackOffset()).
   */
  std::vector<Eigen::Vector3d> trajectoryContinuation( const std::vector<Eigen::Vector3d> &trajectory, const Eigen::Vector3d &last, int stepSign, double length,
                                                       double step, std::optional<double> leftOffsetM = std::nullopt );

  //! A point's place beside the trajectory: arc length along it and signed offset to its left (plan, metres).
  struct TrackCoordinates
  {
    double arcM = 0.0;
    double leftOffsetM = 0.0;
  };

  /**
   * Arc length and left offset of a point (in plan) on the trajectory; the
   * first and last legs extend straight on. Nothing for fewer than two
   * trajectory points.
   */
  std::optional<TrackCoordinates> trackCoordinates( const std::vector<Eigen::Vector3d> &trajectory, const Eigen::Vector2d &xy );

  /**
   * A road line's direction at `point` (block CRS, unit): `lineDirection`,
   * the chord over the line's last stretch (centred at `chordMiddle`),
   * turned as far as the track turns from the chord's middle to the
   * point - on a curve a 20 m chord points several degrees off the line's
   * tangent at its ends and beyond them. The track's heading at a place
   * is the chord of the track 5 m either side of it. `lineDirection`
   * unchanged for fewer than two trajectory points.
   */
  Eigen::Vector3d lineDirectionAt( const std::vector<Eigen::Vector3d> &trajectory, const Eigen::Vector3d &lineDirection, const Eigen::Vector3d &chordMiddle,
                                   const Eigen::Vector3d &point );

  /**
   * The median offset from the trajectory of the line's points within
   * `withinM` along the track of its last one (at least `minPoints` of
   * them, else nothing): where the line goes on, not moved by one stray
   * vertex at its far end (a follower that slid onto the parallel edge
   * beside it).
   */
  std::optional<double> recentTrackOffset( const std::vector<Eigen::Vector3d> &trajectory, const std::vector<Eigen::Vector3d> &line, double withinM, size_t minPoints = 3 );

  /**
   * How many of `points` (in order along a followed line; nothing where a
   * pixel does not reach the ground) stay in the corridor of a road line
   * through `anchor`: parallel to the trajectory, half as wide as
   * `halfWidthM` plus `slope` times the distance along the track from the
   * anchor (road lines run with the road; a merging or diverging line
   * leaves it slowly). A line that jumps across the road - a follower or
   * a bridge that went astray onto another line - is cut where it leaves.
   * All of them without a trajectory.
   */
  size_t pointsInCourse( const std::vector<Eigen::Vector3d> &trajectory, const Eigen::Vector3d &anchor, const std::vector<std::optional<Eigen::Vector3d>> &points,
                         double halfWidthM, double slope );

  /**
   * The road surface under the van's track: the height of the nearest
   * point of the trajectory (camera centres) minus the camera's height
   * above the road; nothing for an empty trajectory.
   */
  std::optional<double> trackSurfaceHeight( const std::vector<Eigen::Vector3d> &trajectory, const Eigen::Vector2d &xy, double cameraHeightM );

  /**
   * The trajectory with its heights smoothed: at each station a quadratic
   * in arc length fitted to the stations within `halfWindowM` (a line with
   * fewer than 5). The road's shape without the stations' independent
   * height errors.
   */
  std::vector<Eigen::Vector3d> smoothedHeights( const std::vector<Eigen::Vector3d> &trajectory, double halfWindowM );

} // namespace geostation

#endif // GEOSTATION_TRACING_TRACKGEOMETRY_H
