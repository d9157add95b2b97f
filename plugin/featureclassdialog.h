/***************************************************************************
  featureclassdialog.h - defining the feature classes of a project
 ***************************************************************************/
#ifndef GEOSTATIONFEATURECLASSDIALOG_H
#define GEOSTATIONFEATURECLASSDIALOG_H

#include <QDialog>

#include "featureclassmodel.h"
#include "ui_geostationfeatureclassdialogbase.h"

class GeoStationFeatureClassDialog : public QDialog, private Ui::GeoStationFeatureClassDialogBase
{
    Q_OBJECT

  public:
    GeoStationFeatureClassDialog( const QList<GeoStationFeatureClass> &classes, QWidget *parent = nullptr );

    QList<GeoStationFeatureClass> classes() const { return mModel->classes(); }
    GeoStationFeatureClassModel *model() const { return mModel; }

  public slots:
    //! Accepts only valid classes; otherwise shows the reason and stays open.
    void accept() override;

  private:
    GeoStationFeatureClassModel *mModel = nullptr;
};

#endif // GEOSTATIONFEATURECLASSDIALOG_H
