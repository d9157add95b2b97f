/***************************************************************************
  importblockalgorithm.h - geostation:import_block
  -------------------------------------------------------------------------
  An oriented block from the photogrammetry ecosystem (a COLMAP sparse
  model, text or binary) as a GeoStation block, optionally georeferenced
  from known camera centres or control points; tie points as tables.
 ***************************************************************************/
#ifndef IMPORTBLOCKALGORITHM_H
#define IMPORTBLOCKALGORITHM_H

#include "geostationalgorithm.h"

#include "geostation_processing_export.h"

namespace GeoStationProcessing
{

class GEOSTATION_PROCESSING_EXPORT ImportBlockAlgorithm : public GeoStationAlgorithm
{
  public:
    QString name() const override;
    QString displayName() const override;
    QStringList tags() const override;
    QString group() const override;
    QString groupId() const override;
    QString helpText() const override;
    ImportBlockAlgorithm *createInstance() const override;

  protected:
    void initAlgorithm( const QVariantMap &configuration = QVariantMap() ) override;
    QVariantMap processGeoStation( const QVariantMap &parameters, QgsProcessingContext &context, QgsProcessingFeedback *feedback ) override;
};

} // namespace GeoStationProcessing

#endif // IMPORTBLOCKALGORITHM_H
