within Bicycle.Mechanics.Frames;
model FrontFrame "Front frame (fork and handlebar): body and front axle"
  constant Integer n = 6 "Number of generalized speeds";
  parameter Bicycle.Units.Length w "Wheelbase w";
  parameter Bicycle.Units.Length c "Trail c";
  parameter Bicycle.Units.Length rF "Front wheel radius rF";
  parameter Bicycle.Units.Position xH "Centre of mass: x coordinate xH (from the rear contact point, forward)";
  parameter Bicycle.Units.Position zH "Centre of mass: z coordinate zH (down; negative above the ground)";
  parameter Bicycle.Units.Mass mH "Mass mH";
  parameter Bicycle.Units.MomentOfInertia IHxx "Inertia-tensor element IHxx about the centre of mass";
  parameter Bicycle.Units.MomentOfInertia IHxz "Inertia-tensor element IHxz about the centre of mass";
  parameter Bicycle.Units.MomentOfInertia IHyy "Inertia-tensor element IHyy about the centre of mass";
  parameter Bicycle.Units.MomentOfInertia IHzz "Inertia-tensor element IHzz about the centre of mass";
  Bicycle.Mechanics.Interfaces.Frame_a frame_a(n = n) "Steer-axis point (on the ground of the nominal configuration); axes parallel to the rear frame's at zero steer";
  Bicycle.Mechanics.Interfaces.Frame_b frame_b(n = n) "Front axle: origin at the front wheel centre, y along the axle";
  Bicycle.Mechanics.Parts.RigidBody body(n = n, m = mH, rx = xH - w - c, rz = zH, Ixx = IHxx, Iyy = IHyy, Izz = IHzz, Ixz = IHxz) "Fork and handlebar";
  Bicycle.Mechanics.Parts.FixedTranslation toAxle(n = n, rx = -c, rz = -rF) "Steer-axis point to the front axle";
equation
  connect(frame_a, body.frame_a);
  connect(frame_a, toAxle.frame_a);
  connect(toAxle.frame_b, frame_b);
  annotation(Documentation(info = "<html><p>The front frame H of Meijaard et al. (2007): a rigid body
with the centre of mass at <code>(xH, zH)</code> from the rear contact point (nominal configuration)
and the front axle at <code>(w, -rF)</code>. Its frame is the steer-axis point with axes parallel
to the rear frame's at zero steer (Meijaard's inertia axes).</p></html>"));
end FrontFrame;
