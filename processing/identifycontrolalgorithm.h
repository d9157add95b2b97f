/***************************************************************************
  identifycontrolalgorithm.h - geostation:identify_control
  -------------------------------------------------------------------------
  Ground control found in one photo without an operator: mark candidates in
  the image, identified with a control layer (core/identification), checked
  by resection. Writes the observations table that resection takes and a
  JSON report (docs/conventions.md §8-9).
 ***************************************************************************/
#ifndef IDENTIFYCONTROLALGORITHM_H
#define IDENTIFYCONTROLALGORITHM_H

#include "geostationalgorithm.h"

#include "geostation_processing_export.h"

namespace GeoStationProcessing
{

class GEOSTATION_PROCESSING_EXPORT IdentifyControlAlgorithm : public GeoStationAlgorithm
{
  public:
    QString name() const override;
    QString displayName() const override;
    QStringList tags() const override;
    QString group() const override;
    QString groupId() const override;
    QString helpText() const override;
    IdentifyControlAlgorithm *createInstance() const override;

  protected:
    void initAlgorithm( const QVariantMap &configuration = QVariantMap() ) override;
    QVariantMap processGeoStation( const QVariantMap &parameters, QgsProcessingContext &context, QgsProcessingFeedback *feedback ) override;
};

} // namespace GeoStationProcessing

#endif // IDENTIFYCONTROLALGORITHM_H
