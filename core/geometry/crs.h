/***************************************************************************
  crs.h - checks on a block's coordinate reference system (docs/conventions.md §4)
 ***************************************************************************/
#ifndef GEOSTATION_GEOMETRY_CRS_H
#define GEOSTATION_GEOMETRY_CRS_H

#include <string>

#include <Eigen/Core>

namespace geostation
{

  struct CrsDescription
  {
    std::string name;     //!< PROJ's name of the CRS, e.g. "WGS 84 / UTM zone 17N"
    std::string kind;     //!< "projected", "engineering", "geographic", "geocentric", ...
    std::string unitName; //!< unit of the first horizontal axis, e.g. "metre"
    double unitToMetre = 0.0;
  };

  /**
   * Describes a CRS given as anything PROJ reads (EPSG:xxxx, WKT, PROJ string).
   * For a compound CRS the horizontal part is described.
   * Throws std::invalid_argument when PROJ does not recognise it.
   */
  CrsDescription describeCrs( const std::string &definition );

  /**
   * Throws std::invalid_argument with a sentence a surveyor understands unless
   * the CRS is projected (or a local engineering CRS) with axes in metres.
   */
  void requireProjectedMetricCrs( const std::string &definition );

  /**
   * The name of the vertical CRS of a compound CRS (e.g. "EGM96 height"), or
   * an empty string for a CRS without one. Throws std::invalid_argument when
   * PROJ does not recognise the CRS.
   */
  std::string verticalCrsName( const std::string &definition );

  /**
   * Coordinates from one CRS to another with PROJ, in the axis order GIS
   * data uses (x = easting / longitude, y = northing / latitude); heights are
   * passed through the transformation: from a 3-D CRS (ellipsoidal heights,
   * geocentric) into a compound CRS with a vertical datum they become heights
   * in that datum through its geoid model. Not thread-safe: one per thread.
   */
  class CrsTransform
  {
    public:
      /**
       * Throws std::invalid_argument when PROJ cannot relate the two CRSs, or
       * cannot bring heights from a 3-D CRS into the vertical datum of
       * `to` because the geoid model is not installed (PROJ would pass them
       * through unchanged).
       */
      CrsTransform( const std::string &from, const std::string &to );
      ~CrsTransform();
      CrsTransform( const CrsTransform & ) = delete;
      CrsTransform &operator=( const CrsTransform & ) = delete;

      //! True when both CRSs are the same: transform() returns its input.
      bool isIdentity() const { return mIdentity; }

      //! Transformed point; NaN components when PROJ fails for it.
      Eigen::Vector3d transform( const Eigen::Vector3d &point ) const;

    private:
      void *mContext = nullptr;
      void *mTransform = nullptr;
      bool mIdentity = false;
  };

} // namespace geostation

#endif // GEOSTATION_GEOMETRY_CRS_H
