/***************************************************************************
  featureschema.h - the field names of measured features (docs/conventions.md §7)
  -------------------------------------------------------------------------
  Defined once for every writer of the GIS database: the measurement store
  of the desktop plugin, the Processing algorithms' vertex tables and the
  review of extracted roads. Feature layers carry the attributes below (the
  worst vertex's sigmas) and the feature class's own; the companion table
  `vertices` holds Xin's (1995) record format, vertex by vertex.
 ***************************************************************************/
#ifndef GEOSTATION_IO_FEATURESCHEMA_H
#define GEOSTATION_IO_FEATURESCHEMA_H

#include <array>

namespace geostation::featureschema
{

  // feature layers
  inline constexpr char kClass[] = "class";
  inline constexpr char kStation[] = "station";
  inline constexpr char kAcquired[] = "acquired";             //!< image time
  inline constexpr char kMeasured[] = "measured";             //!< time of measurement
  inline constexpr char kImageCount[] = "n_images";
  inline constexpr char kSigmaX[] = "sigma_x";                //!< metres, worst vertex
  inline constexpr char kSigmaY[] = "sigma_y";
  inline constexpr char kSigmaZ[] = "sigma_z";
  inline constexpr char kMethod[] = "method";                 //!< vertexMethodName() of the weakest vertex, or traced / extracted
  inline constexpr char kMeasurementId[] = "measurement_id";  //!< joins a feature and its vertex rows before the feature has a fid

  //! The attributes every feature layer has, in order (a feature class's own come after them and may not reuse these, nor "fid").
  inline constexpr std::array<const char *, 10> kFeatureFields { kClass, kStation, kAcquired, kMeasured, kImageCount, kSigmaX, kSigmaY, kSigmaZ, kMethod, kMeasurementId };

  // the companion table
  inline constexpr char kVerticesTable[] = "vertices";
  inline constexpr char kFeatureFid[] = "feature_fid";
  inline constexpr char kVertex[] = "vertex";                 //!< 0-based index along the feature
  inline constexpr char kX[] = "X";                           //!< block CRS
  inline constexpr char kY[] = "Y";
  inline constexpr char kZ[] = "Z";
  inline constexpr char kSx[] = "sx";                         //!< metres
  inline constexpr char kSy[] = "sy";
  inline constexpr char kSz[] = "sz";
  inline constexpr char kImageIds[] = "image_ids";            //!< separated by ';'
  inline constexpr char kResidualsPx[] = "residuals_px";      //!< "dx dy" per image, separated by ';'
  inline constexpr char kLayer[] = "layer";                   //!< the feature's layer (one table serves every layer)

} // namespace geostation::featureschema

#endif // GEOSTATION_IO_FEATURESCHEMA_H
