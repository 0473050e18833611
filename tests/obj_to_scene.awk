# obj_to_scene.awk [-v mirror=1]: an OBJ's triangles (no normals) as trazador `triangle` lines in
# scene coordinates, converted by hand into trazador's left-handed space: z negated (as text, so
# the parser reads the file's very digits), corners 0 2 1; degenerate faces (height under 1e-5 of
# the longest edge) left out, as the mesh loader drops them. mirror=1 keeps the file's own
# coordinates and winding: the mirror image a loader without the conversion showed.
/^v / { n++; x[n] = $2; y[n] = $3; z[n] = mirror ? $4 : substr($4, 1, 1) == "-" ? substr($4, 2) : "-" $4 }
/^f / {
    for (i = 2; i <= 4; i++) { split($i, a, "/"); k[i - 1] = a[1] < 0 ? n + 1 + a[1] : a[1] }
    ax = x[k[2]] - x[k[1]]; ay = y[k[2]] - y[k[1]]; az = z[k[2]] - z[k[1]]
    bx = x[k[3]] - x[k[1]]; by = y[k[3]] - y[k[1]]; bz = z[k[3]] - z[k[1]]
    cx = x[k[3]] - x[k[2]]; cy = y[k[3]] - y[k[2]]; cz = z[k[3]] - z[k[2]]
    l = ax * ax + ay * ay + az * az; m2 = bx * bx + by * by + bz * bz; c2 = cx * cx + cy * cy + cz * cz
    if (m2 > l) l = m2; if (c2 > l) l = c2
    px = ay * bz - az * by; py = az * bx - ax * bz; pz = ax * by - ay * bx
    if (sqrt(px * px + py * py + pz * pz) < 1e-5 * l) { dropped++; next }
    b = mirror ? 2 : 3
    c = mirror ? 3 : 2
    printf "triangle lambertian v0 %s %s %s v1 %s %s %s v2 %s %s %s\n", x[k[1]], y[k[1]], z[k[1]],
        x[k[b]], y[k[b]], z[k[b]], x[k[c]], y[k[c]], z[k[c]]
}
