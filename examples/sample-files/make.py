#!/usr/bin/python3
"""Writes the user-described sample of examples/plan-sim-files.yaml: labels.png (each pixel the
index of its material in the plan's sim.materials: 0 white paint, 1 brass, 2 pink jasper) and
height.png (16-bit, full scale 8 pixels: the brass lettering embossed half a pixel high, its
edges smoothed over about 1.5 pixels). 240 x 240 pixels over the plan's 40 mm: 0.17 mm each.
Run with Debian's python3 (numpy and OpenCV): examples/sample-files/make.py"""
import os

import cv2
import numpy

here = os.path.dirname(os.path.abspath(__file__))
size = 240
labels = numpy.zeros((size, size), numpy.uint8)
cv2.putText(labels, "ACQ", (28, 110), cv2.FONT_HERSHEY_SIMPLEX, 2.6, 1, thickness=9)
labels[150:200, 30:110] = 2            # a pink-jasper patch
labels[150:200, 140:143] = 1           # a brass rule three pixels wide
cv2.imwrite(os.path.join(here, "labels.png"), labels)
height = cv2.GaussianBlur((labels == 1).astype(numpy.float32) * 0.5, (0, 0), 1.5)
cv2.imwrite(os.path.join(here, "height.png"), numpy.round(height / 8 * 65535).astype(numpy.uint16))
