/***************************************************************************
  featureschema.h - the field names GeoStation writes and reads (docs/conventions.md §6, §7)
  -------------------------------------------------------------------------
  Defined once for every writer of the GIS database: the measurement store
  of the desktop plugin, the Processing algorithms' vertex tables and the
  review of extracted roads. Feature layers carry the attributes below (the
  worst vertex's sigmas) and the feature class's own; the companion table
  `vertices` holds Xin's (1995) record format, vertex by vertex. Then the
  fields of the tables the Processing algorithms exchange (observations,
  per-feature outcomes, road lines, map revision), which the plugin's review
  panels read back.
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

  // the algorithms' tables (docs/conventions.md §6, §8)
  inline constexpr char kPointId[] = "point_id";
  inline constexpr char kImageId[] = "image_id";
  inline constexpr char kCol[] = "col";                       //!< pixel, docs/conventions.md §1
  inline constexpr char kRow[] = "row";
  inline constexpr char kSigmaPx[] = "sigma_px";
  inline constexpr char kStatus[] = "status";                 //!< a per-feature or per-row outcome
  inline constexpr char kMessage[] = "message";               //!< one sentence beside a status that is not ok
  inline constexpr char kRole[] = "role";                     //!< control or check

  // road lines: extracted, traced, merged, joined
  inline constexpr char kLineId[] = "line_id";
  inline constexpr char kAcceptedIn[] = "accepted_in";        //!< the images an extracted line was verified in
  inline constexpr char kLengthM[] = "length_m";
  inline constexpr char kSigmaMax[] = "sigma_max";            //!< metres, the line's worst vertex
  inline constexpr char kSeedId[] = "seed_id";
  inline constexpr char kStopReason[] = "stop_reason";

  // map revision
  inline constexpr char kRevision[] = "revision";             //!< confirmed, moved, not_found, occluded, outside, invalid_geometry
  inline constexpr char kEvidence[] = "evidence";             //!< 0-1
  inline constexpr char kShiftM[] = "shift_m";
  inline constexpr char kSourceFid[] = "source_fid";          //!< the map feature a piece comes from
  inline constexpr char kReview[] = "review";                 //!< the operator's decision
  inline constexpr char kMapPart[] = "map_part";              //!< the part of a multi-part map feature (from 0)
  inline constexpr char kMapFromM[] = "map_from_m";           //!< where a piece begins along its map road (m from the road's first vertex)
  inline constexpr char kMapToM[] = "map_to_m";
  inline constexpr char kMapM[] = "map_m";                    //!< a vertex's place along its map road (m)
  inline constexpr char kPairs[] = "pairs";                   //!< the stereo pairs a merged line or piece comes from, separated by ';'
  inline constexpr char kPiece[] = "piece";                   //!< a vertex table's row: the piece (the output's row, from 1)

} // namespace geostation::featureschema

#endif // GEOSTATION_IO_FEATURESCHEMA_H
