#!/usr/bin/python3
"""Writes the fuzz targets' seed corpus (tests/fuzz/corpus/<target>/).

Small, valid inputs of every format a target reads, and a few near misses,
so that libFuzzer starts from inputs that reach deep into each reader. Run
again after changing it; the files are kept in the repository.

    /usr/bin/python3 tests/fuzz/makecorpus.py
"""
import os
import shutil
import struct

import numpy as np
from osgeo import gdal, osr

HERE = os.path.dirname(os.path.abspath(__file__))
SOURCE = os.path.dirname(os.path.dirname(HERE))
CORPUS = os.path.join(HERE, "corpus")


def write(target, name, data):
    folder = os.path.join(CORPUS, target)
    os.makedirs(folder, exist_ok=True)
    mode = "wb" if isinstance(data, bytes) else "w"
    with open(os.path.join(folder, name), mode) as f:
        f.write(data)


def block_json():
    with open(os.path.join(SOURCE, "docs", "examples", "sample.geostation.json")) as f:
        sample = f.read()
    write("block_json", "sample.json", sample)
    write("block_json", "minimal.json",
          '{"format": "geostation-block", "version": 1, "crs": "EPSG:25832", "cameras": [], "images": []}\n')
    write("block_json", "oriented.json",
          '{"format": "geostation-block", "version": 1, "crs": "EPSG:25832",\n'
          ' "cameras": [{"id": "c", "width": 64, "height": 48, "f": 50.0, "cx": 32.0, "cy": 24.0,\n'
          '   "distortion": {"model": "none"}}],\n'
          ' "stations": [{"id": "S1"}],\n'
          ' "images": [{"id": "a", "camera": "c", "station": "S1", "path": "a.png",\n'
          '   "X": 1.5, "Y": -2.25, "Z": 1e3, "omega": 0, "phi": 0, "kappa": -180}]}\n')
    write("block_json", "wrong_type.json", sample.replace('"f": 812.4', '"f": "812.4"'))
    write("block_json", "truncated.json", sample[: len(sample) // 2])


COLMAP_CAMERAS = """# Camera list with one line of data per camera:
#   CAMERA_ID, MODEL, WIDTH, HEIGHT, PARAMS[]
1 PINHOLE 64 48 50.5 51 32 24
2 SIMPLE_RADIAL 64 48 50 32 24 -0.01
3 OPENCV 64 48 50 50 32 24 -0.1 0.01 0.001 -0.002
4 FULL_OPENCV 64 48 50 50 32 24 -0.1 0.01 0.001 -0.002 0 0 0 0
5 SIMPLE_PINHOLE 64 48 50 32 24
6 RADIAL 64 48 50 32 24 -0.1 0.01
"""
COLMAP_IMAGES = """# Image list with two lines of data per image:
#   IMAGE_ID, QW, QX, QY, QZ, TX, TY, TZ, CAMERA_ID, NAME
#   POINTS2D[] as (X, Y, POINT3D_ID)
1 1 0 0 0 0 0 0 1 a.png
10.5 20.25 1 30 40 -1
2 0.99500416527802582 0.099833416646828155 0 0 -1 0.5 0.25 3 b.png
11.5 21.25 1 5 6 -1
3 0 1 0 0 2 0 0 5 c.png

"""
COLMAP_POINTS = """# 3D point list with one line of data per point:
#   POINT3D_ID, X, Y, Z, R, G, B, ERROR, TRACK[] as (IMAGE_ID, POINT2D_IDX)
1 0.5 0.25 10 255 128 0 0.5 1 0 2 0
"""


def colmap_text():
    write("colmap_text", "model.txt", COLMAP_CAMERAS + "%%\n" + COLMAP_IMAGES + "%%\n" + COLMAP_POINTS)
    write("colmap_text", "posed_only.txt", COLMAP_CAMERAS + "%%\n" + COLMAP_IMAGES)
    write("colmap_text", "bad_model.txt", COLMAP_CAMERAS.replace("PINHOLE 64", "PINHOL 64") + "%%\n" + COLMAP_IMAGES)
    # COLMAP 3.12: a rig of cameras 1 and 3 (and an IMU) and its frames; image 3 in no frame
    rigs = ("# Rig calib list with one line of data per calib:\n"
            "1 3 CAMERA 1 CAMERA 3 1 0.70710678118654757 0 0.70710678118654757 0 -0.5 0 0.25 IMU 1 0\n"
            "2 1 CAMERA 5\n")
    frames = ("# Frame list with one line of data per frame:\n"
              "1 1 1 0 0 0 0 0 0 3 CAMERA 1 1 CAMERA 3 2 IMU 1 50\n"
              "2 2 0 1 0 0 2 0 0 0\n")
    write("colmap_text", "rig_model.txt", COLMAP_CAMERAS + "%%\n" + COLMAP_IMAGES + "%%\n" + COLMAP_POINTS + "%%\n" + rigs + "%%\n" + frames)


def colmap_binary():
    # layouts of COLMAP's src/base/reconstruction.cc: little-endian, counts as uint64
    cameras = struct.pack("<Q", 2)
    cameras += struct.pack("<IiQQ", 1, 1, 64, 48) + struct.pack("<4d", 50.5, 51, 32, 24)  # PINHOLE
    cameras += struct.pack("<IiQQ", 2, 4, 64, 48) + struct.pack("<8d", 50, 50, 32, 24, -0.1, 0.01, 0.001, -0.002)  # OPENCV
    images = struct.pack("<Q", 2)
    images += struct.pack("<I4d3dI", 1, 1, 0, 0, 0, 0, 0, 0, 1) + b"a.png\0" + struct.pack("<Q", 2)
    images += struct.pack("<ddQ", 10.5, 20.25, 1) + struct.pack("<ddQ", 30, 40, 0xFFFFFFFFFFFFFFFF)
    images += struct.pack("<I4d3dI", 2, 0.995, 0.0998, 0, 0, -1, 0.5, 0.25, 2) + b"b.png\0" + struct.pack("<Q", 1)
    images += struct.pack("<ddQ", 11.5, 21.25, 1)
    points = struct.pack("<Q", 1) + struct.pack("<Q3d3Bd", 1, 0.5, 0.25, 10, 255, 128, 0, 0.5)
    points += struct.pack("<Q", 2) + struct.pack("<II", 1, 0) + struct.pack("<II", 2, 0)
    write("colmap_binary", "model.bin", cameras + b"\n%%\n" + images + b"\n%%\n" + points)
    write("colmap_binary", "posed_only.bin", cameras + b"\n%%\n" + images)
    # COLMAP 3.12 (src/colmap/scene/reconstruction_io_binary.cc): a rig of both cameras, one frame of both images
    rigs = struct.pack("<Q", 1) + struct.pack("<IIiI", 1, 2, 0, 1) + struct.pack("<iIB", 0, 2, 1) + struct.pack("<7d", 1, 0, 0, 0, -0.5, 0, 0)
    frames = struct.pack("<Q", 1) + struct.pack("<II7dI", 1, 1, 1, 0, 0, 0, 0, 0, 0, 2)
    frames += struct.pack("<iIQ", 0, 1, 1) + struct.pack("<iIQ", 0, 2, 2)
    write("colmap_binary", "rig_model.bin", cameras + b"\n%%\n" + images + b"\n%%\n" + points + b"\n%%\n" + rigs + b"\n%%\n" + frames)


def trajectory_csv():
    write("trajectory_csv", "latlon.csv",
          "time,station,latitude,longitude,height,roll,pitch,heading,image_front\n"
          "2025-05-01T10:00:00.0Z,P1,40.0,-78.0,200.0,0,0,0,img/a.png\n"
          "2025-05-01T10:00:01.0Z,P2,40.0001,-78.0,200.1,0,0,0,img/b.png\n"
          "2025-05-01T10:00:02.0Z,P3,40.0002,-78.0,200.2,1.5,-0.5,10,img/c.png\n")
    write("trajectory_csv", "grid_semicolon.csv",
          "image;X;Y;Z;omega;phi;kappa\n"
          "a.png;500100.25;4400200.5;310.0;0.5;-0.25;91.0\n"
          "b.png;500150.25;4400200.5;311.0;0.25;0.5;-179.5\n")
    write("trajectory_csv", "easting_tab.csv",
          "station\teasting\tnorthing\theight\troll\tpitch\tyaw\n"
          "S1\t500100\t4400200\t310\t0.01\t0.02\t1.5\n")
    write("trajectory_csv", "quoted.csv",
          '"station","X","Y","Z","roll","pitch","heading"\n'
          '"S 1",500100,4400200,310,0,0,"90"\n')


def events_csv():
    write("events_csv", "iso.csv",
          "time,station\n"
          "2026-05-04T10:00:00.050Z,A\n"
          "2026-05-04 11:00:00.500+01:00,B\n"
          "2026-05-04T10:00:01.000Z,C\n")
    write("events_csv", "outside_and_image_column.csv",
          "gps_time;id;image\n"
          "2026-05-04T09:00:00Z;early;a.png\n"
          "2026-05-04T10:00:00.3Z;ok;b.png\n")


def metashape_xml():
    sensor = ('<sensor id="0" label="cam0" type="frame">\n<resolution width="600" height="400"/>\n'
              '<calibration type="frame" class="adjusted">\n<resolution width="600" height="400"/>\n'
              '<f>510</f><cx>3.25</cx><cy>-2.5</cy><b1>1.5</b1><b2>0</b2><k1>-0.11</k1><k2>0.02</k2>'
              '<k3>0.003</k3><k4>0</k4><p1>0.0004</p1><p2>-0.0002</p2>\n</calibration>\n</sensor>\n')
    camera = ('<camera id="0" sensor_id="0" label="DSC0001"><transform>1 0 0 12.5 0 1 0 -3.25 0 0 1 40 0 0 0 1'
              '</transform></camera>\n<camera id="1" sensor_id="0" label="DSC0002"/>\n')
    head = '<?xml version="1.0" encoding="UTF-8"?>\n<document version="1.5.0">\n<chunk label="Chunk 1" enabled="true">\n'
    write("metashape_xml", "local.xml", head + '<sensors next_id="1">\n' + sensor + '</sensors>\n<cameras next_id="2">\n'
          + camera + '</cameras>\n</chunk>\n</document>\n')
    write("metashape_xml", "referenced.xml", head + '<sensors next_id="1">\n' + sensor + '</sensors>\n<cameras next_id="2">\n'
          + camera + '</cameras>\n<transform><rotation>1 0 0 0 1 0 0 0 1</rotation>'
          '<translation>4517000 -6000 4490000</translation><scale>1.5</scale></transform>\n'
          '<reference>GEOGCS["WGS 84",DATUM["World Geodetic System 1984",SPHEROID["WGS 84",6378137,298.257223563]],'
          'PRIMEM["Greenwich",0],UNIT["degree",0.01745329251994328],AUTHORITY["EPSG","4326"]]</reference>\n'
          '</chunk>\n</document>\n')
    write("metashape_xml", "broken.xml", head + '<sensors>\n' + sensor)
    markers = ('<markers>\n<marker id="0" label="GCP1"><reference x="-78.1" y="40.2" z="250" sx="0.02" sy="0.02" sz="0.05" enabled="true"/></marker>\n'
               '<marker id="1" label="GCP2"><reference x="-78.1001" y="40.2" z="251" enabled="false"/></marker>\n<marker id="2" label="tie"/>\n</markers>\n'
               '<frames><frame id="0"><markers>\n<marker marker_id="0"><location camera_id="0" pinned="true" x="310.5" y="180.25"/>'
               '<location camera_id="1" pinned="true" x="10" y="10"/></marker>\n'
               '<marker marker_id="1"><location camera_id="0" pinned="false" x="250" y="190"/></marker>\n</markers></frame></frames>\n')
    write("metashape_xml", "markers.xml", head + '<sensors next_id="1">\n' + sensor + '</sensors>\n<cameras next_id="2">\n'
          + camera + '</cameras>\n' + markers + '<transform><rotation>1 0 0 0 1 0 0 0 1</rotation>'
          '<translation>4517000 -6000 4490000</translation><scale>1.5</scale></transform>\n'
          '<reference>GEOGCS["WGS 84",DATUM["World Geodetic System 1984",SPHEROID["WGS 84",6378137,298.257223563]],'
          'PRIMEM["Greenwich",0],UNIT["degree",0.01745329251994328],AUTHORITY["EPSG","4326"]]</reference>\n'
          '</chunk>\n</document>\n')


def opencv_calibration():
    write("opencv_calibration", "single.yaml",
          "%YAML:1.0\n---\nimage_width: 1920\nimage_height: 1080\n"
          "camera_matrix: !!opencv-matrix\n   rows: 3\n   cols: 3\n   dt: d\n"
          "   data: [ 1400.5, 0., 959.25, 0., 1401., 539.75, 0., 0., 1. ]\n"
          "distortion_coefficients: !!opencv-matrix\n   rows: 1\n   cols: 5\n   dt: d\n"
          "   data: [ -0.21, 0.05, 0.001, -0.0005, 0.002 ]\n")
    write("opencv_calibration", "rig.yaml",
          "%YAML:1.0\ncameras:\n  - id: front\n    image_width: 64\n    image_height: 48\n"
          "    camera_matrix: !!opencv-matrix\n      rows: 3\n      cols: 3\n      dt: d\n"
          "      data: [ 50., 0., 31.5, 0., 50., 23.5, 0., 0., 1. ]\n"
          "    distortion_coefficients: [ -0.1, 0.01, 0., 0. ]\n    lever_arm: [ 1.0, 0.0, -2.0 ]\n"
          "    boresight: [ 0., -10., 0. ]\n    image_pattern: \"img/{station}_front.png\"\n"
          "  - id: right\n    image_width: 64\n    image_height: 48\n"
          "    camera_matrix: [ 50., 0., 31.5, 0., 50., 23.5, 0., 0., 1. ]\n"
          "    distortion_coefficients: [ ]\n    lever_arm: [ 0.0, 0.8, -2.0 ]\n    boresight: [ 0., 0., 90. ]\n")
    write("opencv_calibration", "single.xml",
          '<?xml version="1.0"?>\n<opencv_storage>\n<image_width>640</image_width>\n<image_height>480</image_height>\n'
          '<camera_matrix type_id="opencv-matrix">\n  <rows>3</rows>\n  <cols>3</cols>\n  <dt>d</dt>\n'
          '  <data>500. 0. 319.5 0. 500. 239.5 0. 0. 1.</data></camera_matrix>\n'
          '<distortion_coefficients type_id="opencv-matrix">\n  <rows>8</rows>\n  <cols>1</cols>\n  <dt>d</dt>\n'
          '  <data>-0.1 0.01 0. 0. 0. 0. 0. 0.</data></distortion_coefficients>\n</opencv_storage>\n')


def raster_bytes(driver, array, options=None, geo=False, gcps=False, metadata=None):
    path = "/vsimem/corpus"
    bands = 1 if array.ndim == 2 else array.shape[2]
    gdal_type = gdal.GDT_UInt16 if array.dtype == np.uint16 else gdal.GDT_Float32 if array.dtype == np.float32 else gdal.GDT_Byte
    mem = gdal.GetDriverByName("MEM").Create("", array.shape[1], array.shape[0], bands, gdal_type)
    for b in range(bands):
        mem.GetRasterBand(b + 1).WriteArray(array if bands == 1 else array[:, :, b])
    if geo:
        mem.SetGeoTransform((500000.0, 2.0, 0.0, 4400064.0, 0.0, -2.0))
        srs = osr.SpatialReference()
        srs.ImportFromEPSG(32617)
        mem.SetProjection(srs.ExportToWkt())
        mem.GetRasterBand(1).SetNoDataValue(-9999 if array.dtype == np.float32 else 0)
    if gcps:
        srs = osr.SpatialReference()
        srs.ImportFromEPSG(4326)
        mem.SetGCPs([gdal.GCP(-80.0 + 0.01 * i, 40.0 + 0.01 * j, 0.0, 15.0 * i, 15.0 * j) for i in (0, 1) for j in (0, 1)], srs.ExportToWkt())
    if metadata:
        mem.SetMetadata(metadata)
    gdal.GetDriverByName(driver).CreateCopy(path, mem, options=options or [])
    f = gdal.VSIFOpenL(path, "rb")
    gdal.VSIFSeekL(f, 0, 2)
    size = gdal.VSIFTellL(f)
    gdal.VSIFSeekL(f, 0, 0)
    data = gdal.VSIFReadL(1, size, f)
    gdal.VSIFCloseL(f)
    gdal.Unlink(path)
    return bytes(data)


def raster():
    rng = np.random.default_rng(7)
    grey = (np.add.outer(np.arange(16), np.arange(16)) * 8 + rng.integers(0, 8, (16, 16))).astype(np.uint8)
    rgb = np.dstack([grey, grey[::-1], grey.T]).astype(np.uint8)
    deep = (grey.astype(np.uint16) * 257)
    write("raster", "grey.png", raster_bytes("PNG", grey))
    write("raster", "rgb.jpg", raster_bytes("JPEG", rgb, ["QUALITY=80"]))
    write("raster", "deep.tif", raster_bytes("GTiff", deep))
    write("raster", "rgb_deflate_tiled.tif", raster_bytes("GTiff", rgb, ["COMPRESS=DEFLATE", "TILED=YES", "BLOCKXSIZE=16", "BLOCKYSIZE=16"]))
    write("raster", "rgba.png", raster_bytes("PNG", np.dstack([rgb, grey])))
    # photos the Multiview shows in their pixels (pixelSpaceSource), turned and mirrored as tagged
    write("raster", "georeferenced.tif", raster_bytes("GTiff", grey, geo=True))
    write("raster", "gcps.tif", raster_bytes("GTiff", rgb, gcps=True))
    write("raster", "turned.jpg", raster_bytes("JPEG", grey, ["QUALITY=80"], metadata={"EXIF_Orientation": "6"}))
    write("raster", "transposed.jpg", raster_bytes("JPEG", grey, ["QUALITY=80"], metadata={"EXIF_Orientation": "5"}))


def dem():
    x, y = np.meshgrid(np.arange(32), np.arange(32))
    heights = (200.0 + 3.0 * np.sin(x / 5.0) + 0.2 * y).astype(np.float32)
    holed = heights.copy()
    holed[4:7, 4:7] = -9999
    holed[12:26, 10:28] = -9999
    write("dem", "hills.tif", raster_bytes("GTiff", heights, geo=True))
    write("dem", "holes.tif", raster_bytes("GTiff", holed, geo=True))
    write("dem", "integer_lzw.tif", raster_bytes("GTiff", (heights * 10).astype(np.uint16), ["COMPRESS=LZW"], geo=True))


if __name__ == "__main__":
    shutil.rmtree(CORPUS, ignore_errors=True)
    block_json()
    colmap_text()
    colmap_binary()
    trajectory_csv()
    events_csv()
    metashape_xml()
    opencv_calibration()
    raster()
    dem()
    for target in sorted(os.listdir(CORPUS)):
        print(target, len(os.listdir(os.path.join(CORPUS, target))), "files")
