"""Renders `acq export pbr`'s glTF in Blender (Cycles, CPU) at the geometry of `acq render view`'s
defaults: the camera 1 m above the sample's centre looking straight down, a point light 1 m
away at zenith --light-theta-deg and azimuth --light-phi-deg. Writes a linear EXR (for
tools/chart_export.py). The glTF is imported as a user would (File > Import > glTF 2.0).

  blender -b --factory-startup -P tools/render_blender.py -- GLTF OUT.exr
      [--light-theta-deg 30] [--light-phi-deg 0] [--width 256] [--spp 64] [--seed 0]

Runs inside Blender's own Python (bpy); Blender comes from Debian (tools/setup.sh
--viewers). docs/export.md, "Opening the export".
"""
import argparse
import math
import os
import sys

import bpy
import numpy

# Debian 12's Blender 3.4 glTF importer calls numpy.bool, which Debian's numpy 1.24 no longer
# has (the alias was deprecated in 1.20): it fails on any glTF with "module 'numpy' has no
# attribute 'bool'". The alias restored for this process only.
if "bool" not in numpy.__dict__:
    numpy.bool = bool

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from view_geometry import DISTANCE_M, add_arguments, light_position_m  # noqa: E402


def parse():
    argv = sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else []
    p = argparse.ArgumentParser(prog="render_blender.py")
    p.add_argument("gltf")
    p.add_argument("out")
    add_arguments(p)
    p.add_argument("--spp", type=int, default=64)
    p.add_argument("--seed", type=int, default=0)  # Cycles' sampling seed
    return p.parse_args(argv)


def import_sample(path):
    bpy.ops.wm.read_factory_settings(use_empty=True)
    bpy.ops.import_scene.gltf(filepath=path)
    meshes = [o for o in bpy.context.scene.objects if o.type == "MESH"]
    if len(meshes) != 1:
        raise SystemExit(f"render_blender.py: {path}: expected one mesh (the sample), got {len(meshes)}")
    return meshes[0]


def add_camera(scene, sample):
    data = bpy.data.cameras.new("camera")
    data.sensor_fit = "HORIZONTAL"
    data.angle = 2 * math.atan(sample.dimensions.x / 2 / DISTANCE_M)
    camera = bpy.data.objects.new("camera", data)
    camera.location = (0, 0, DISTANCE_M)  # Blender's camera looks down its -Z: straight down
    scene.collection.objects.link(camera)
    scene.camera = camera


def add_light(scene, theta_deg, phi_deg):
    data = bpy.data.lights.new("light", type="POINT")
    data.shadow_soft_size = 0  # a point, as ours
    data.energy = 1000
    light = bpy.data.objects.new("light", data)
    light.location = light_position_m(theta_deg, phi_deg)  # Blender's Z up is the sample's z
    scene.collection.objects.link(light)


def main():
    a = parse()
    sample = import_sample(a.gltf)
    scene = bpy.context.scene
    add_camera(scene, sample)
    add_light(scene, a.light_theta_deg, a.light_phi_deg)
    scene.world = bpy.data.worlds.new("black")
    scene.world.color = (0, 0, 0)
    scene.render.engine = "CYCLES"
    scene.cycles.device = "CPU"
    scene.cycles.samples = a.spp
    scene.cycles.seed = a.seed
    scene.cycles.use_denoising = False
    scene.render.resolution_x = a.width
    scene.render.resolution_y = max(1, round(a.width * sample.dimensions.y / sample.dimensions.x))
    scene.render.resolution_percentage = 100
    scene.view_settings.view_transform = "Standard"
    scene.render.image_settings.file_format = "OPEN_EXR"
    scene.render.image_settings.color_depth = "32"
    scene.render.filepath = a.out
    bpy.ops.render.render(write_still=True)
    print(f"wrote {a.out}")


main()
