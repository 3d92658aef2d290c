#!/bin/sh
# Remake the ParaView pictures in docs/images/ (see docs/render/README.md). Run from the repository
# root after `cargo build --release`; needs pvpython (ParaView 5.11) and xvfb-run.
set -eu
FLEXMB=${FLEXMB:-target/release/flexmb}     # or the binary of a clean checkout
W=${TMPDIR:-/tmp}/flexmb_render
RENDER="xvfb-run -a pvpython docs/render/render_frame.py"
mkdir -p "$W"

# 1. the door, opened 30° on misaligned hinges: at t = 0 it is deflected to fit both hinges
$FLEXMB run models/door/door.toml --vtk "$W/door_vtk" --out "$W/out" --t-end 0.8 --output-step 0.005 --quiet
$RENDER "$W/door_vtk/door.pvd" 0 docs/images/door_deformed.png --warp 50 --undeformed \
    --view=-0.95,0.2,-0.4 --size 900 1000 --line bottom_hinge top_hinge \
    --note 'grey bar: the hinge line'

# 2. the windshield wiper at t = 0.65 s, the largest arm deflection of the first 0.8 s; the crank and
#    the links are drawn as the shapes of their [[body]] tables
$FLEXMB run models/wiper/wiper.toml --vtk "$W/wiper_vtk" --out "$W/out" --t-end 0.8 --quiet
$RENDER "$W/wiper_vtk/wiper.pvd" 0.65 docs/images/wiper_frame.png --warp 5 --undeformed --view=-z

# 3. the flexible pendulum (README) at t = 0.3 s
$FLEXMB run models/flexible_pendulum.toml --vtk "$W/fp_vtk" --out "$W/out" --quiet
$RENDER "$W/fp_vtk/flexible_pendulum.pvd" 0.3 docs/images/flexible_pendulum_frame.png --warp 100 \
    --undeformed --view=-z

# 4. the door's first mode (4N5S), a quarter period into its animation (largest displacement)
$FLEXMB modes models/door/door_fe.toml --modes 4N5S --out "$W/out/door_4N5S.json" --vtk "$W/modes_vtk" > /dev/null
$RENDER "$W/modes_vtk/door_mode_O1.pvd" 0.25 docs/images/door_mode_shape.png --array displacement \
    --undeformed --view=-1,0.5,-0.4 --size 900 1000 --title "door (4N5S): mode O1, 12.56 Hz, a twist"

# 5. the solid pendulum's link 3 ms after its release, coloured by von Mises stress (its hot spot)
$FLEXMB run models/solid_pendulum.toml --vtk "$W/link_vtk" --out "$W/out" --vtk-step 0.001 --t-end 0.02 --quiet
$RENDER "$W/link_vtk/solid_pendulum.pvd" 0.003 docs/images/solid_link_stress.png --color von_mises \
    --warp 1000 --undeformed --view=0.35,-0.5,-1 --up=0,1,0 --size 1200 600 \
    --title "solid link (20 C3D20, 4N): von Mises stress at t = 3 ms"
