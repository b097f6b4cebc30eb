# Imports a baked glTF into Blender 3.4 (Debian's) and renders it from a photonbake camera sidecar, with no light
# of Blender's own: what an artist sees after importing the bake (issue 21). The picture shows the baked light only
# if Blender reads COLOR_0 and the unlit materials as they are meant.
#   blender -b --python-exit-code 1 --python tools/blender-view-gltf.py -- BAKE.glb SCENE.camera.json OUT.png
import bpy, json, math, sys
import numpy
from mathutils import Vector
numpy.bool = bool  # Blender 3.4's glTF importer uses numpy.bool, which Debian 12's numpy 1.24 no longer has
glb, camera_path, out = sys.argv[sys.argv.index("--") + 1:][:3]
bpy.ops.wm.read_factory_settings(use_empty=True)
bpy.ops.import_scene.gltf(filepath=glb)
scene = bpy.context.scene
to_blender = lambda p: Vector((p[0], -p[2], p[1]))  # glTF is y-up; Blender's importer turns it z-up
cam = json.load(open(camera_path))
data = bpy.data.cameras.new("camera")
data.sensor_fit = 'VERTICAL'
data.angle_y = math.radians(cam["vertical_fov_deg"])
camera = bpy.data.objects.new("camera", data)
scene.collection.objects.link(camera)
camera.location = to_blender(cam["position_m"])
direction = to_blender(cam["look_at_m"]) - camera.location
camera.rotation_euler = direction.to_track_quat('-Z', 'Y').to_euler()
scene.camera = camera
scene.world = bpy.data.worlds.new("black")
scene.world.color = (0, 0, 0)
scene.render.engine = 'CYCLES'
scene.cycles.samples = 16
scene.cycles.use_denoising = False
scene.render.resolution_x = scene.render.resolution_y = 384
scene.view_settings.view_transform = 'Standard'  # COLOR_0 is already tone-mapped
scene.render.filepath = out
bpy.ops.render.render(write_still=True)
print("materials:", [(m.name, [n.type for n in m.node_tree.nodes]) for m in bpy.data.materials if m.node_tree])
