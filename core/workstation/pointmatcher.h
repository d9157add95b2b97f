/***************************************************************************
  pointmatcher.h - a point measured in one image found in another image of
  the block (what geostation:match_points does for every row)
  -------------------------------------------------------------------------
  Two oriented images: the search runs along the epipolar band of the point
  (depths EpipolarOptions::minDistanceM .. maxDistanceM), with the window's
  shape predicted on the terrain when one is given. Otherwise: within
  searchRadiusPx of an approximate position in the target. Images come from
  a MatchImageCache: each is prepared once (or, too large to prepare whole,
  in the window the match reads), and an image that cannot be read is
  remembered and named in the reason of every match that needs it.
  Expected failures (the point outside its image, the curve missing the
  target, no peak, ...) come back as the AreaMatch's status and message.
 ***************************************************************************/
#ifndef GEOSTATION_WORKSTATION_POINTMATCHER_H
#define GEOSTATION_WORKSTATION_POINTMATCHER_H

#include <map>
#include <memory>
#include <optional>
#include <string>

#include <Eigen/Core>

#include "geometry/epipolar.h"
#include "geometry/windowshape.h"
#include "io/block.h"
#include "matching/areamatcher.h"
#include "workstation/matchimagecache.h"

namespace geostation
{

  struct PointMatchOptions
  {
    AreaMatchOptions area;
    EpipolarOptions epipolar;
    double searchRadiusPx = 20.0; //!< around the approximate position, images not both oriented
    GroundOfPixel terrain;        //!< optional: the window's shape predicted on it (oriented images)

    //! Throws std::invalid_argument naming the first bad value.
    void check() const;
  };

  class PointMatcher
  {
    public:
      //! The block and the cache are referenced: they must outlive the matcher. Throws for bad options.
      PointMatcher( const Block &block, const PointMatchOptions &options, MatchImageCache &cache );

      /**
       * Finds `pixelInReference` (pixelInImage of `reference`) in `target`:
       * along the epipolar band when both are oriented, else around
       * `approximateInTarget` (needed then).
       */
      AreaMatch match( const BlockImage &reference, const Eigen::Vector2d &pixelInReference, const BlockImage &target,
                       const std::optional<Eigen::Vector2d> &approximateInTarget ) const;

    private:
      //! The prepared image (or the window `window` asks for, for an image too large to prepare whole); nullptr if unreadable.
      std::shared_ptr<const MatchImage> imageFor( const BlockImage &image, const std::function<cv::Rect( const cv::Size & )> &window ) const;

      const Block &mBlock;
      PointMatchOptions mOptions;
      MatchImageCache &mCache;
      mutable std::map<std::string, std::string> mUnreadable; //!< image id: why it cannot be read
  };

} // namespace geostation

#endif // GEOSTATION_WORKSTATION_POINTMATCHER_H
