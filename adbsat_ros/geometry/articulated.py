"""Articulated satellites: a URDF's links and joints as panels for any joint configuration.
Joints fixed, revolute, continuous, prismatic, mimic; at zero the panels equal the parts merged
into one mesh, bit for bit. Units m, rad; mesh frame G = the root link's frame."""

from __future__ import annotations

import io
import math
import os
from dataclasses import dataclass
from typing import TYPE_CHECKING, Mapping

import numpy as np

from adbsat_ros.geometry.mesh import (
    DEFAULT_MATERIAL,
    MeshError,
    MeshReport,
    PanelMesh,
    check_size,
    panels_from_arrays,
    triangle_geometry,
)
from adbsat_ros.geometry.mesh_files import read_mesh_file
from adbsat_ros.geometry.poses import JointTree

if TYPE_CHECKING:
    import trimesh
    import yourdfpy

#: Sections around a URDF cylinder, and subdivisions of a URDF sphere's icosphere.
CYLINDER_SECTIONS = 48
SPHERE_SUBDIVISIONS = 3
#: A URDF box or cylinder is refined until no edge is longer than this fraction of its size.
EDGE_FRACTION = 1.0 / 12.0


@dataclass(frozen=True)
class BodyLoads:
    """Per-link Cf and Cm (body frame; summing to Cf_G, Cm_G), and per moving joint the
    coefficient of its axis moment (revolute; times q A_ref L_ref: N m) or axial force
    (prismatic; times q A_ref: N)."""

    link_force: np.ndarray
    link_moment: np.ndarray
    joint_effort: dict


@dataclass
class _Part:
    link: int
    vertices: np.ndarray  # (V, 3) in the link's frame [m]
    faces: np.ndarray  # (F, 3), oriented, zero-area faces dropped
    material: int
    own: tuple = ()  # normals, areas, barycentres of its panels in the link's frame
    at_zero: tuple = ()  # the same in the body frame at the zero configuration


def _moved(points: np.ndarray, pose: np.ndarray) -> np.ndarray:
    """Points (n, 3) [m] of a link's frame in the frame of its 4 x 4 ``pose``."""
    return points @ pose[:3, :3].T + pose[:3, 3]


def _primitive(geometry, max_edge_fraction: float, resolve) -> trimesh.Trimesh:
    """The triangles of a URDF geometry in its visual frame [m]."""
    import trimesh  # (when a body is built: not at start-up)

    if geometry.box is not None:
        size = np.asarray(geometry.box.size, dtype=float)
        box = trimesh.creation.box(extents=size)
        v, f = trimesh.remesh.subdivide_to_size(
            box.vertices, box.faces, max_edge=max_edge_fraction * float(size.max())
        )
        return trimesh.Trimesh(v, f, process=False)
    if geometry.cylinder is not None:
        c = geometry.cylinder
        return trimesh.creation.cylinder(
            radius=float(c.radius), height=float(c.length), sections=CYLINDER_SECTIONS
        )
    if geometry.sphere is not None:
        return trimesh.creation.icosphere(
            subdivisions=SPHERE_SUBDIVISIONS, radius=float(geometry.sphere.radius)
        )
    if geometry.mesh is not None:
        arrays = read_mesh_file(resolve(geometry.mesh.filename))  # (MeshError names it)
        tm = trimesh.Trimesh(arrays.vertices, arrays.faces, process=False)
        scale = geometry.mesh.scale
        if scale is not None:
            tm.apply_scale(np.broadcast_to(np.asarray(scale, dtype=float), (3,)))
        return tm
    raise MeshError("a URDF visual or collision without geometry")


class ArticulatedBody:
    """A satellite of links and joints from a URDF (:meth:`from_urdf`), as panels in any pose.
    ``joints``: the moving joints by name; ``root``: the link whose frame is the body frame;
    ``panel_link``: each panel's link; ``link_spans``: each link's (start, stop) of panels."""

    def __init__(
        self,
        urdf: yourdfpy.URDF,
        source: str,
        max_edge_fraction=EDGE_FRACTION,
        accept_size: bool = False,
    ):
        self.source = source
        self._tree = JointTree(urdf, source)
        self.root, self.links = self._tree.root, self._tree.links
        self.joints, self.all_joint_names = self._tree.joints, self._tree.all_joint_names
        directory = os.path.dirname(os.path.abspath(source)) if os.path.isfile(source) else "."

        def resolve(filename):
            import yourdfpy

            return yourdfpy.filename_handler_magic(filename, dir=directory)

        names, parts, reports = [], [], []
        kind = "visuals" if any(k.visuals for k in urdf.link_map.values()) else "collisions"
        for index, link_name in enumerate(self.links):
            for element in getattr(urdf.link_map[link_name], kind):
                tm = _primitive(element.geometry, max_edge_fraction, resolve)
                if element.origin is not None:
                    tm.apply_transform(np.asarray(element.origin, dtype=float))
                material = getattr(getattr(element, "material", None), "name", None)
                material = material or DEFAULT_MATERIAL
                if material not in names:
                    names.append(material)
                checked = panels_from_arrays(
                    tm.vertices, tm.faces, source=f"{source}: link {link_name}"
                )
                reports.append(checked.report)
                parts.append(_Part(index, *self._faces_of(tm, checked), names.index(material)))
        if not parts:
            raise MeshError(f"{source}: no link has geometry (no visual, no collision)")
        self._zero_poses = self.link_poses()
        for part in parts:
            part.own = triangle_geometry(part.vertices[part.faces])
            part.at_zero = triangle_geometry(
                _moved(part.vertices, self._zero_poses[part.link])[part.faces]
            )
        self._parts = parts
        self.material_names = tuple(names)
        self.panel_link = np.concatenate([np.full(len(p.faces), p.link) for p in parts])
        self.link_spans = {}
        for link in np.unique(self.panel_link):  # (parts are made link by link)
            where = np.flatnonzero(self.panel_link == link)
            self.link_spans[int(link)] = (int(where[0]), int(where[-1]) + 1)
        counts = ("dropped_zero_area", "flipped_components", "open_components", "components")
        self._report = MeshReport(
            **{name: sum(getattr(r, name) for r in reports) for name in counts},
            watertight=all(r.watertight for r in reports),
            convex=False,
        )
        if not accept_size:
            check_size(source, self.mesh())

    @staticmethod
    def _faces_of(tm, checked) -> tuple:
        """A part's vertices and faces as ``checked`` keeps them (oriented, none of zero area)."""
        vertices = np.asarray(tm.vertices, dtype=float)
        faces = np.asarray(tm.faces)
        tri = vertices[faces]
        keep = {tuple(t.ravel()): i for i, t in enumerate(tri)}
        out = []
        for panel in checked.vertices:
            i = keep.get(tuple(panel.ravel()))
            out.append(faces[i] if i is not None else faces[keep[tuple(panel[::-1].ravel())]][::-1])
        return vertices, np.asarray(out)

    @classmethod
    def from_urdf(
        cls,
        urdf,
        max_edge_fraction: float = EDGE_FRACTION,
        accept_size: bool = False,
        source: str | None = None,
    ) -> "ArticulatedBody":
        """Read a URDF: a file path, or its XML text (as the ``robot_description`` parameter).
        Meshes found relative to the URDF (``package://`` by yourdfpy); 1 mm to 200 m across unless
        ``accept_size``. MeshError: naming the file and element (unreadable, unsupported...)."""
        text = str(urdf)
        is_xml = text.lstrip().startswith("<")
        path = None if is_xml else os.fspath(urdf)
        source = source or path or "robot_description"
        import yourdfpy  # (when a URDF is read: not at start-up)

        try:
            stream = io.StringIO(text) if is_xml else path
            # (no scene graph: JointTree makes the one it poses the links with)
            model = yourdfpy.URDF.load(stream, build_scene_graph=False, load_meshes=False)
        except Exception as exc:  # (OSError, URDFError, lxml's XMLSyntaxError and the like)
            raise MeshError(f"{source}: not a readable URDF: {exc}") from None
        return cls(model, source, max_edge_fraction, accept_size)

    def positions(self, values: Mapping[str, float] | None = None) -> dict:
        """``{name: value}`` [rad or m] of every moving joint, completed with zeros.
        ValueError: an unknown joint, or a value non-finite or outside its limits."""
        out = {name: 0.0 for name in self.joints}
        for name, value in (values or {}).items():
            joint = self.joints.get(name)
            if joint is None:
                raise ValueError(
                    f"joint {name!r} is not a moving joint of {self.source}; its joints are "
                    f"{', '.join(self.joints) or 'none'}"
                )
            try:
                number = float(value)
            except (TypeError, ValueError):
                raise ValueError(
                    f"joint {name}: position must be a number, got {value!r}"
                ) from None
            if not math.isfinite(number):
                raise ValueError(f"joint {name}: position must be finite, got {value!r}")
            if not joint.lower <= number <= joint.upper:
                unit = "m" if joint.kind == "prismatic" else "rad"
                raise ValueError(
                    f"joint {name}: position {number!r} {unit} is outside its limits "
                    f"[{joint.lower:g}, {joint.upper:g}] {unit}"
                )
            out[name] = number
        return out

    def link_poses(self, values: Mapping[str, float] | None = None) -> np.ndarray:
        """4 x 4 pose of every link in the body frame, shape (L, 4, 4), for joint ``values``."""
        return self._tree.poses(self.positions(values))

    def mesh(self, values: Mapping[str, float] | None = None) -> PanelMesh:
        """The panels of the configuration ``values`` (joint name to position; others at 0)."""
        return self.posed_mesh(self.link_poses(values))

    def posed_mesh(self, poses: np.ndarray) -> PanelMesh:
        """The panels with the links at ``poses`` (L, 4, 4)."""
        return self._panels(self._parts, poses)

    def link_mesh(self, link: int) -> PanelMesh:
        """The panels of link index ``link`` in its own frame, in the order of :meth:`mesh`."""
        parts = [p for p in self._parts if p.link == link]
        if not parts:
            raise ValueError(f"link {self.links[link]} has no geometry")
        return self._panels(parts, np.broadcast_to(np.eye(4), (len(self.links), 4, 4)))

    def _panels(self, parts, poses) -> PanelMesh:
        n = sum(len(part.faces) for part in parts)
        tri, areas = np.empty((n, 3, 3)), np.empty(n)
        normals, barycentres = np.empty((n, 3)), np.empty((n, 3))
        materials, start = [], 0
        for part in parts:
            pose = poses[part.link]
            stop = start + len(part.faces)
            np.take(_moved(part.vertices, pose), part.faces, axis=0, out=tri[start:stop])
            if np.array_equal(pose, self._zero_poses[part.link]):
                normals[start:stop], areas[start:stop], barycentres[start:stop] = part.at_zero
            else:
                own_normals, areas[start:stop], own_barycentres = part.own
                normals[start:stop] = own_normals @ pose[:3, :3].T
                barycentres[start:stop] = _moved(own_barycentres, pose)
            materials.append(np.full(len(part.faces), part.material))
            start = stop
        return PanelMesh(
            vertices=tri,
            normals=normals,
            areas=areas,
            barycentres=barycentres,
            material_index=np.ascontiguousarray(np.concatenate(materials)),
            material_names=self.material_names,
            report=self._report,
            source=self.source,
        )

    def carried_links(self, joint: str) -> np.ndarray:
        """Indices of the links a joint carries: its child and every link beyond it."""
        return np.array(sorted(map(self.links.index, self._tree.carried(self.joints[joint].child))))

    def loads(self, force, point, values, moment_point, length) -> BodyLoads:
        """:class:`BodyLoads` of per-panel force coefficients ``force`` acting at ``point`` [m]."""
        force = np.asarray(force, dtype=float)
        point = np.asarray(point, dtype=float)
        moments = np.cross(point - np.asarray(moment_point, dtype=float), force) / length
        n_links = len(self.links)
        link_force = np.zeros((n_links, 3))
        link_moment = np.zeros((n_links, 3))
        for k in range(3):
            link_force[:, k] = np.bincount(self.panel_link, force[:, k], minlength=n_links)
            link_moment[:, k] = np.bincount(self.panel_link, moments[:, k], minlength=n_links)
        poses = self.link_poses(values)
        effort = {}
        for name, joint in self.joints.items():
            child = poses[self.links.index(joint.child)]
            axis = child[:3, :3] @ np.asarray(joint.axis, dtype=float)
            axis /= np.linalg.norm(axis)
            carried = np.isin(self.panel_link, self.carried_links(name))
            f = force[carried]
            if joint.kind == "prismatic":
                effort[name] = float(f.sum(axis=0) @ axis)
            else:
                arm = point[carried] - child[:3, 3]
                effort[name] = float(np.cross(arm, f).sum(axis=0) @ axis) / length
        return BodyLoads(link_force, link_moment, effort)

    def parts(self, values: Mapping[str, float] | None = None) -> list:
        """``(link name, vertices, faces, material name)`` of every part, body frame."""
        poses = self.link_poses(values)
        return [
            (
                self.links[p.link],
                _moved(p.vertices, poses[p.link]),
                p.faces,
                self.material_names[p.material],
            )
            for p in self._parts
        ]
