/***************************************************************************
  geostationalgorithm.h - the base of GeoStation's Processing algorithms
  -------------------------------------------------------------------------
  QGIS catches only QgsProcessingException from an algorithm (in
  qgis_process, in the Processing dialog's background task and in models):
  any other exception ends QGIS. Core reports failures it cannot foresee
  (a corrupt DEM tile met in the middle of a batch, memory running out) as
  std::exception; this base turns them into one QgsProcessingException
  that names the algorithm and says what happened.
 ***************************************************************************/
#ifndef GEOSTATIONALGORITHM_H
#define GEOSTATIONALGORITHM_H

#include <qgsprocessingalgorithm.h>

#include "geostation_processing_export.h"

namespace GeoStationProcessing
{

class GEOSTATION_PROCESSING_EXPORT GeoStationAlgorithm : public QgsProcessingAlgorithm
{
  protected:
    //! The algorithm's work (what processAlgorithm() is for other algorithms).
    virtual QVariantMap processGeoStation( const QVariantMap &parameters, QgsProcessingContext &context, QgsProcessingFeedback *feedback ) = 0;

    /**
     * Runs processGeoStation(); a std::exception from it becomes a
     * QgsProcessingException with its message, std::bad_alloc one that
     * says memory ran out.
     */
    QVariantMap processAlgorithm( const QVariantMap &parameters, QgsProcessingContext &context, QgsProcessingFeedback *feedback ) final;
};

} // namespace GeoStationProcessing

#endif // GEOSTATIONALGORITHM_H
