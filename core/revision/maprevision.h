/***************************************************************************
  maprevision.h - an existing road map held against a new stereo pair
  -------------------------------------------------------------------------
  Each road of the map is carried into both images through the terrain
  (the DEM, or the height the pair itself gives) and checked sample by
  sample, a few pixels apart along its course:

    confirmed  a road band (crossprofile.h: either polarity, the widths
               looked for) lies on the mapped course in both images,
               within the map's tolerance;
    moved      not there, but within SHIFT_MAX of it a band runs in the
               first image whose ground point shows a band in the second
               too: the road is now there;
    not_found  neither;
    outside    the course is not seen by both images.

  A sample's status is the majority of its neighbours' (a car or a
  shadow over one sample does not split a road), and each road is split
  where its status changes. The confirmed and moved pieces are measured
  again from their band centres in both images: the rays intersected
  where the road crosses the epipolar direction at 35 degrees or more,
  else the first image's ray on the terrain; a sigma per vertex. The
  others keep the map's course. The pair's own extraction (roadnetworkextractor.h), run
  first for the terrain height and the widths, supplies the roads no map
  road explains: the new roads.

  Frames: map roads and results in the block CRS (metres); a map road's
  vertices may have no height (NaN z): the terrain gives it.
 ***************************************************************************/
#ifndef GEOSTATION_REVISION_MAPREVISION_H
#define GEOSTATION_REVISION_MAPREVISION_H

#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "extraction/roadnetworkextractor.h"
#include "geometry/projection.h"

namespace geostation
{

  enum class RevisionStatus
  {
    Confirmed,
    Moved,
    NotFound,
    Outside,
    Occluded,        //!< not found where a surface model (MapRevisionOptions::surface) hides the course from a camera
    InvalidGeometry, //!< fewer than two distinct vertices
  };

  //! "confirmed", "moved", "not_found", "outside", "occluded", "invalid_geometry".
  std::string revisionStatusName( RevisionStatus status );
  //! The status of one of those names; none for any other text.
  std::optional<RevisionStatus> revisionStatusFromName( const std::string &name );

  struct MapRevisionOptions
  {
    RoadNetworkOptions network = defaultRoadNetworkOptions(); //!< the pair's extraction (terrain height, widths, new roads)
    std::optional<double> shiftMaxM;  //!< how far a road may have moved; default 1.5 x the widest road (RoadNetworkOptions::roadWidthM), else 40 px
    double toleranceM = 2.0;          //!< the map's own accuracy: a band within this (and 2 px) of the mapped course confirms it
    double sampleSpacingPx = 0.0;     //!< along the map roads in the first image; 0: the narrowest road's width, at least 4 px
    int majorityHalfWindow = 3;       //!< a sample's status: the majority within this many samples either side
    //! Where a sample's short profiles (1.5 px along the course) show no road, profiles averaged over this many
    //! metres either side along it are looked at too (past a car, a marking's dash, a tree's shadow); 0: short ones only.
    double longProfileM = 8.0;
    bool findNewRoads = true;         //!< false: the pair is not extracted (faster); its set-up only (RoadNetworkOptions::extract), no new roads
    double newGapM = 0.0;             //!< an extracted line farther than this from every map road and revised course is new; 0: 3 x the tolerance, at least 10 px
    /**
     * The first point a ray meets on a surface model (a DSM with buildings
     * and trees, or the DEM for hills), nullopt where it meets none; none
     * given: nothing is occluded. A sample not found whose ray from either
     * camera meets the surface more than `occlusionClearanceM` above it is
     * occluded, not gone.
     */
    std::function<std::optional<Eigen::Vector3d>( const Ray &ray )> surface;
    double occlusionClearanceM = 2.0;

    //! Throws std::invalid_argument naming the first bad value.
    void check() const;
  };

  struct MapRoad
  {
    std::vector<Eigen::Vector3d> vertices; //!< block CRS; z NaN where the map has no height
  };

  //! A stretch of one map road with one status.
  struct RevisedPiece
  {
    size_t road = 0; //!< index into the map roads
    RevisionStatus status = RevisionStatus::NotFound;
    double evidence = 0.0;                  //!< 0-1: the share of its samples whose own status agrees
    double shiftM = 0.0;                    //!< moved: the median distance from the mapped course (XY)
    std::vector<Eigen::Vector3d> course;    //!< the revised course (confirmed, moved), else the map's
    std::vector<Eigen::Vector3d> sigmaM;    //!< per vertex of a measured course (x, y, z); empty for the map's
    std::vector<bool> heightByStereo;       //!< per vertex of a measured course: intersected rays (else the terrain's height, sigma its spread; 0 for a DEM or a given height)
    //! Where the piece lies along the map road: metres (XY) from the road's first vertex to the piece's first and last sample
    double fromM = 0.0, toM = 0.0;
    std::vector<double> alongMapM;          //!< per vertex of `course`: the place along the map road of the sample it stands for
    double lengthM() const;
  };

  struct MapRevisionSummary
  {
    std::vector<RevisedPiece> pieces;          //!< in the order of the map roads, along each
    std::vector<NetworkLine> newRoads;         //!< extracted and explained by no map road
    RoadNetworkSummary extraction;             //!< the pair's own extraction
    double shiftMaxM = 0.0, toleranceM = 0.0;  //!< as used
    double groundPixelM = 0.0;
    int samples = 0;
    double seconds = 0.0;  //!< the whole revision
    bool cancelled = false;
    //! Total length of the pieces with `status` (m, along their courses).
    double lengthM( RevisionStatus status ) const;
  };

  /**
   * Revises `map` against the oriented pair (a, b) read through `greyA`,
   * `greyB` and `matching` (as extractRoadNetwork). Throws
   * std::invalid_argument for bad options or a pair that is no stereo pair
   * (as extractRoadNetwork); a map road with fewer than two distinct
   * vertices is one piece `invalid_geometry`; roads the pair does not see
   * are `outside`.
   */
  MapRevisionSummary reviseRoads( const GreyTiles &greyA, const GreyTiles &greyB, PairMatchWindows &matching, const OrientedImage &a, const OrientedImage &b,
                                  const std::vector<MapRoad> &map, const MapRevisionOptions &options, const Progress &progress = Progress() );

  //! The same for a pair of raster files, read a window at a time (as extractRoadNetwork).
  MapRevisionSummary reviseRoads( std::shared_ptr<const RasterReader> readerA, std::shared_ptr<const RasterReader> readerB, const OrientedImage &a, const OrientedImage &b,
                                  const std::vector<MapRoad> &map, const MapRevisionOptions &options, const Progress &progress = Progress() );

  //! The same for two images held whole.
  MapRevisionSummary reviseRoads( const MatchImage &imageA, const MatchImage &imageB, const OrientedImage &a, const OrientedImage &b,
                                  const std::vector<MapRoad> &map, const MapRevisionOptions &options, const Progress &progress = Progress() );

  /**
   * A map line with one stretch replaced by a moved road's course: the
   * course's two ends are projected onto the line (the nearest points of
   * its course, XY), and the line runs from its start to the first, along
   * the course, and from the second to its end (a course running against
   * the line is turned first). Throws std::invalid_argument for a line or
   * course of fewer than two points.
   */
  std::vector<Eigen::Vector3d> spliceCourse( const std::vector<Eigen::Vector3d> &line, const std::vector<Eigen::Vector3d> &course );

} // namespace geostation

#endif // GEOSTATION_REVISION_MAPREVISION_H
