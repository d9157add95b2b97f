/***************************************************************************
  networkintersection.h - the extracted network in 3-D (issue: 3-D lines)
  -------------------------------------------------------------------------
  Each vertex of a line of image A (every few pixels) is matched in image
  B along its epipolar curve: where the curve crosses a line of B's
  network at a good angle, the crossing is the conjugate point (its
  precision along the curve is the line's across-precision over the sine
  of the angle); where the line runs along the epipolar direction, the
  crossing is undetermined and the point is matched by area correlation
  and least squares along the curve instead (only LSM matches count).
  The two rays are intersected, with the covariance of the intersection.
 ***************************************************************************/
#ifndef GEOSTATION_EXTRACTION_NETWORKINTERSECTION_H
#define GEOSTATION_EXTRACTION_NETWORKINTERSECTION_H

#include <string>
#include <vector>

#include <Eigen/Core>

#include "extraction/pairmapping.h"
#include "extraction/pairmatchwindows.h"
#include "extraction/resultmatrix.h"
#include "matching/areamatcher.h"
#include "matching/matchimage.h"

namespace geostation
{

  struct NetworkIntersectionOptions
  {
    double vertexSpacingPx = 6.0;   //!< along the lines of A
    double lineSigmaPx = 0.5;       //!< across-line precision of an extracted line's centre, once moved onto its band (centrerefinement.h; measured: median 0.15 px off, 75 % within 0.35 px)
    double minCrossingAngleDeg = 35.0; //!< below: area matching
    double searchPx = 12.0;         //!< conjugate within this of the mapped position
    double heightRangeM = 60.0;     //!< the epipolar curve spans the mapped height +- this
    int maxGapVertices = 2;         //!< a line is split where more vertices in a row have no conjugate
    AreaMatchOptions areaMatch;     //!< for vertices along the epipolar direction (31 x 31: the road and its surroundings; the correlation peak, unambiguous)

    NetworkIntersectionOptions()
    {
      areaMatch.windowWidth = 31;
      areaMatch.windowHeight = 31;
      areaMatch.minScore = 0.7;
      areaMatch.lsm = false;           // noisy, low-contrast surroundings: least squares often fails its fit check where the peak is clear
      areaMatch.ambiguityMargin = 0.1; // a second peak within 0.1: ambiguous
    }
  };

  struct NetworkVertex
  {
    Eigen::Vector3d point = Eigen::Vector3d::Zero(); //!< block CRS, metres
    Eigen::Vector3d sigmaM = Eigen::Vector3d::Zero();
    Eigen::Vector2d inA = Eigen::Vector2d::Zero(), inB = Eigen::Vector2d::Zero();
    std::string method; //!< "line_crossing" or "area_match"
  };

  struct NetworkLine
  {
    std::vector<NetworkVertex> vertices;
    int sourceLine = 0; //!< index into the lines of A

    //! Along the vertices, in 3-D (m).
    double lengthM() const;
    //! The largest vertex sigma of any coordinate (m).
    double sigmaMaxM() const;
  };

  struct NetworkIntersectionSummary
  {
    std::vector<NetworkLine> lines;
    int vertices = 0, byCrossing = 0, byArea = 0, unmatched = 0;
  };

  /**
   * 3-D lines from the final networks of A and B, matching along the
   * epipolar direction in the pixels `images` provides (in windows for
   * images too large to hold whole); without them (not available()) such
   * vertices stay unmatched. Read errors propagate.
   */
  NetworkIntersectionSummary intersectNetwork( const OrientedPairMapping &mapping, const std::vector<CompiledPolygon> &linesA,
                                               const std::vector<CompiledPolygon> &linesB, PairMatchWindows &images,
                                               const NetworkIntersectionOptions &options = NetworkIntersectionOptions() );

  //! The same over two whole images; `imageA` / `imageB` may be empty.
  NetworkIntersectionSummary intersectNetwork( const OrientedPairMapping &mapping, const std::vector<CompiledPolygon> &linesA,
                                               const std::vector<CompiledPolygon> &linesB, const MatchImage &imageA, const MatchImage &imageB,
                                               const NetworkIntersectionOptions &options = NetworkIntersectionOptions() );

} // namespace geostation

#endif // GEOSTATION_EXTRACTION_NETWORKINTERSECTION_H
