/***************************************************************************
  measurementsettingsdialog.h - where measurements go, single-image settings
 ***************************************************************************/
#ifndef GEOSTATIONMEASUREMENTSETTINGSDIALOG_H
#define GEOSTATIONMEASUREMENTSETTINGSDIALOG_H

#include <QDialog>

#include "ui_geostationmeasurementsettingsdialogbase.h"

class GeoStationMultiviewSession;
class GeoStationMeasurementStore;

class GeoStationMeasurementSettingsDialog : public QDialog, private Ui::GeoStationMeasurementSettingsDialogBase
{
    Q_OBJECT

  public:
    GeoStationMeasurementSettingsDialog( GeoStationMultiviewSession *session, GeoStationMeasurementStore *store, QWidget *parent = nullptr );

  public slots:
    //! Applies the settings; a GeoPackage that cannot be written is reported and the dialog stays open.
    void accept() override;

  private:
    GeoStationMultiviewSession *mSession;
    GeoStationMeasurementStore *mStore;
};

#endif // GEOSTATIONMEASUREMENTSETTINGSDIALOG_H
