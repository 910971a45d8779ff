#!/usr/bin/env python3
"""Writes the test meshes of this folder: an ASCII STL block and a Collada (.dae) block.

    make_meshes.py           # rewrites models/mesh_block/meshes/block.stl and tall_red.dae

Both are boxes standing on z = 0 (base centred on the origin), so a test knows where every face
is: block.stl 0.4 x 0.4 x 0.4 m; tall_red.dae 0.4 x 0.4 x 0.6 m, written with <up_axis>Z_UP</up_axis>
and a red diffuse material (a wrong up axis would lay it on its side).
"""
import os

HERE = os.path.dirname(os.path.abspath(__file__))


def box(sx, sy, sz):
    """Vertices and outward-wound triangles of a box on z = 0."""
    hx, hy = sx / 2, sy / 2
    v = [(x, y, z) for z in (0.0, sz) for y in (-hy, hy) for x in (-hx, hx)]
    quads = [(0, 2, 3, 1), (4, 5, 7, 6), (0, 1, 5, 4), (2, 6, 7, 3), (0, 4, 6, 2), (1, 3, 7, 5)]
    tris = []
    for a, b, c, d in quads:
        tris += [(a, b, c), (a, c, d)]
    return v, tris


def write_stl(path, v, tris):
    with open(path, "w") as f:
        f.write("solid block\n")
        for t in tris:
            f.write("  facet normal 0 0 0\n    outer loop\n")
            for i in t:
                f.write("      vertex %g %g %g\n" % v[i])
            f.write("    endloop\n  endfacet\n")
        f.write("endsolid block\n")


def write_dae(path, v, tris):
    positions = " ".join("%g %g %g" % p for p in v)
    indices = " ".join("%d" % i for t in tris for i in t)
    with open(path, "w") as f:
        f.write(f"""<?xml version="1.0" encoding="utf-8"?>
<COLLADA xmlns="http://www.collada.org/2005/11/COLLADASchema" version="1.4.1">
  <asset><unit name="meter" meter="1"/><up_axis>Z_UP</up_axis></asset>
  <library_effects>
    <effect id="red-effect"><profile_COMMON><technique sid="common"><lambert>
      <diffuse><color>1 0 0 1</color></diffuse>
    </lambert></technique></profile_COMMON></effect>
  </library_effects>
  <library_materials>
    <material id="red" name="red"><instance_effect url="#red-effect"/></material>
  </library_materials>
  <library_geometries>
    <geometry id="box-mesh" name="box">
      <mesh>
        <source id="box-positions">
          <float_array id="box-positions-array" count="{3 * len(v)}">{positions}</float_array>
          <technique_common>
            <accessor source="#box-positions-array" count="{len(v)}" stride="3">
              <param name="X" type="float"/><param name="Y" type="float"/><param name="Z" type="float"/>
            </accessor>
          </technique_common>
        </source>
        <vertices id="box-vertices"><input semantic="POSITION" source="#box-positions"/></vertices>
        <triangles material="red" count="{len(tris)}">
          <input semantic="VERTEX" source="#box-vertices" offset="0"/>
          <p>{indices}</p>
        </triangles>
      </mesh>
    </geometry>
  </library_geometries>
  <library_visual_scenes>
    <visual_scene id="scene">
      <node id="box-node" name="box">
        <instance_geometry url="#box-mesh">
          <bind_material><technique_common>
            <instance_material symbol="red" target="#red"/>
          </technique_common></bind_material>
        </instance_geometry>
      </node>
    </visual_scene>
  </library_visual_scenes>
  <scene><instance_visual_scene url="#scene"/></scene>
</COLLADA>
""")


if __name__ == "__main__":
    meshes = os.path.join(HERE, "models", "mesh_block", "meshes")
    write_stl(os.path.join(meshes, "block.stl"), *box(0.4, 0.4, 0.4))
    write_dae(os.path.join(meshes, "tall_red.dae"), *box(0.4, 0.4, 0.6))
