/***************************************************************************
  exportblockalgorithm.h - geostation:export_block
  -------------------------------------------------------------------------
  A block handed back: a COLMAP text model (cameras, images and, when
  given, tie points) or a CSV of the exterior orientations.
 ***************************************************************************/
#ifndef EXPORTBLOCKALGORITHM_H
#define EXPORTBLOCKALGORITHM_H

#include "geostationalgorithm.h"

#include "geostation_processing_export.h"

namespace GeoStationProcessing
{

class GEOSTATION_PROCESSING_EXPORT ExportBlockAlgorithm : public GeoStationAlgorithm
{
  public:
    QString name() const override;
    QString displayName() const override;
    QStringList tags() const override;
    QString group() const override;
    QString groupId() const override;
    QString helpText() const override;
    ExportBlockAlgorithm *createInstance() const override;

  protected:
    void initAlgorithm( const QVariantMap &configuration = QVariantMap() ) override;
    QVariantMap processGeoStation( const QVariantMap &parameters, QgsProcessingContext &context, QgsProcessingFeedback *feedback ) override;
};

} // namespace GeoStationProcessing

#endif // EXPORTBLOCKALGORITHM_H
