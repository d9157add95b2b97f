/***************************************************************************
  exportmeasurementsalgorithm.h - geostation:export_measurements
 ***************************************************************************/
#ifndef EXPORTMEASUREMENTSALGORITHM_H
#define EXPORTMEASUREMENTSALGORITHM_H

#include "geostationalgorithm.h"

#include "geostation_processing_export.h"

namespace GeoStationProcessing
{

class GEOSTATION_PROCESSING_EXPORT ExportMeasurementsAlgorithm : public GeoStationAlgorithm
{
  public:
    QString name() const override;
    QString displayName() const override;
    QStringList tags() const override;
    QString group() const override;
    QString groupId() const override;
    QString helpText() const override;
    ExportMeasurementsAlgorithm *createInstance() const override;

  protected:
    void initAlgorithm( const QVariantMap &configuration = QVariantMap() ) override;
    QVariantMap processGeoStation( const QVariantMap &parameters, QgsProcessingContext &context, QgsProcessingFeedback *feedback ) override;
};

} // namespace GeoStationProcessing

#endif // EXPORTMEASUREMENTSALGORITHM_H
