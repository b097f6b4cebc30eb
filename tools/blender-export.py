# Builds a small scene in Blender 3.4 (Debian's) and exports it with both of its OBJ exporters, the C++ one
# (wm.obj_export) and the legacy Python one (export_scene.obj), in every texture path mode: what users' files look
# like (issue 19). The scene: a floor without material, a metal cube (Principled metallic), a glass sphere
# (Principled transmission), a PNG- and a JPEG-textured panel whose images lie outside the export folder, an
# L-shaped concave n-gon without material or UV map, and an emissive panel facing down.
#   blender -b --python-exit-code 1 --python tools/blender-export.py -- OUT_DIR
# It also writes the scene as glTF (scene.glb, scene_separate.gltf + .bin + images).
# tests/data/blender holds the absolute-mode exports (their texture paths lead nowhere on another machine) with the
# images beside them; obj_as_written_test.cpp bakes them.
import bpy, os, sys
out = sys.argv[sys.argv.index("--") + 1]
os.makedirs(out, exist_ok=True)
bpy.ops.wm.read_factory_settings(use_empty=True)
scene = bpy.context.scene

def material(name, **inputs):
    m = bpy.data.materials.new(name)
    m.use_nodes = True
    bsdf = m.node_tree.nodes["Principled BSDF"]
    for key, value in inputs.items():
        bsdf.inputs[key].default_value = value
    return m

# An image texture outside the export folder (absolute path mode writes it as is) in PNG and JPEG.
texdir = os.path.join(out, "..", "bl-textures")
os.makedirs(texdir, exist_ok=True)
for ext, fmt in (("png", "PNG"), ("jpg", "JPEG")):
    img = bpy.data.images.new("checker_" + ext, 4, 4)
    img.generated_type = 'COLOR_GRID'
    scene.render.image_settings.file_format = fmt  # Image.save() would write a PNG whatever the name
    img.save_render(os.path.join(texdir, "Checker." + ext), scene=scene)

def textured(name, ext):
    m = bpy.data.materials.new(name)
    m.use_nodes = True
    nodes = m.node_tree.nodes
    tex = nodes.new("ShaderNodeTexImage")
    tex.image = bpy.data.images.load(os.path.join(texdir, "Checker." + ext))
    m.node_tree.links.new(tex.outputs["Color"], nodes["Principled BSDF"].inputs["Base Color"])
    return m

# Floor without material, an L-shaped floor piece (concave n-gon), a metal cube, a glass sphere, textured panels,
# and an emissive panel facing down.
bpy.ops.mesh.primitive_plane_add(size=4, location=(0, 0, 0))
bpy.ops.mesh.primitive_cube_add(size=0.5, location=(0.8, 0.8, 0.25))
bpy.context.object.data.materials.append(material("Metal", **{"Metallic": 1.0, "Roughness": 0.3}))
bpy.ops.mesh.primitive_uv_sphere_add(radius=0.3, location=(-0.8, 0.8, 0.3))
bpy.context.object.data.materials.append(material("Glass", **{"Transmission": 1.0, "Roughness": 0.0, "IOR": 1.45}))
bpy.ops.mesh.primitive_plane_add(size=0.8, location=(-0.8, -0.8, 0.01))
bpy.context.object.data.materials.append(textured("TexPng", "png"))
bpy.ops.mesh.primitive_plane_add(size=0.8, location=(0.8, -0.8, 0.01))
bpy.context.object.data.materials.append(textured("TexJpg", "jpg"))
import bmesh
mesh = bpy.data.meshes.new("LShape")
bm = bmesh.new()
vs = [bm.verts.new(p) for p in [(0, 0, 0.02), (1, 0, 0.02), (1, 0.5, 0.02), (0.5, 0.5, 0.02), (0.5, 1, 0.02), (0, 1, 0.02)]]
bm.faces.new(vs)
bm.to_mesh(mesh)
obj = bpy.data.objects.new("LShape", mesh)
scene.collection.objects.link(obj)
bpy.ops.mesh.primitive_plane_add(size=0.5, location=(0, 0, 2.0), rotation=(3.14159265, 0, 0))
bpy.context.object.data.materials.append(material("Lamp", **{"Emission": (1, 1, 1, 1), "Emission Strength": 10.0}))

for mode in ("AUTO", "ABSOLUTE", "RELATIVE", "STRIP", "COPY"):
    bpy.ops.wm.obj_export(filepath=os.path.join(out, "new_%s.obj" % mode.lower()), path_mode=mode,
                          export_materials=True, forward_axis='Y', up_axis='Z')
    bpy.ops.export_scene.obj(filepath=os.path.join(out, "legacy_%s.obj" % mode.lower()), path_mode=mode,
                             use_materials=True, axis_forward='Y', axis_up='Z')
bpy.ops.wm.obj_export(filepath=os.path.join(out, "new_nomaterials.obj"), export_materials=False,
                      forward_axis='Y', up_axis='Z')

# glTF 2.0 as Blender's exporter writes it (issue 21): one binary .glb with its images inside, and a .gltf with a
# separate .bin and its images beside it.
bpy.ops.export_scene.gltf(filepath=os.path.join(out, "scene.glb"), export_format='GLB')
bpy.ops.export_scene.gltf(filepath=os.path.join(out, "scene_separate.gltf"), export_format='GLTF_SEPARATE')
