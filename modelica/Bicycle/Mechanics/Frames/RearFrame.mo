within Bicycle.Mechanics.Frames;
model RearFrame "Rear frame (rider rigidly attached): body, rear axle, steer-head location"
  constant Integer n = 6 "Number of generalized speeds";
  parameter Bicycle.Units.Length w "Wheelbase w";
  parameter Bicycle.Units.Length c "Trail c";
  parameter Bicycle.Units.Length rR "Rear wheel radius rR (height of the rear axle of the upright bicycle)";
  parameter Bicycle.Units.Position xB "Centre of mass: x coordinate xB (from the rear contact point, forward)";
  parameter Bicycle.Units.Position zB "Centre of mass: z coordinate zB (down; negative above the ground)";
  parameter Bicycle.Units.Mass mB "Mass mB";
  parameter Bicycle.Units.MomentOfInertia IBxx "Inertia-tensor element IBxx about the centre of mass";
  parameter Bicycle.Units.MomentOfInertia IBxz "Inertia-tensor element IBxz about the centre of mass";
  parameter Bicycle.Units.MomentOfInertia IByy "Inertia-tensor element IByy about the centre of mass";
  parameter Bicycle.Units.MomentOfInertia IBzz "Inertia-tensor element IBzz about the centre of mass";
  Bicycle.Mechanics.Interfaces.Frame_a frame_a(n = n) "Rear axle: origin at the rear wheel centre, x forward, y along the axle (right), z down in the frame's plane";
  Bicycle.Mechanics.Interfaces.Frame_b frame_b(n = n) "Steer-head location: the point of the steer axis on the ground of the nominal configuration, axes as frame_a";
  Bicycle.Mechanics.Parts.RigidBody body(n = n, m = mB, rx = xB, rz = zB + rR, Ixx = IBxx, Iyy = IByy, Izz = IBzz, Ixz = IBxz) "Rear frame body with the rider";
  Bicycle.Mechanics.Parts.FixedTranslation toSteerAxis(n = n, rx = w + c, rz = rR) "Rear axle to the steer axis";
equation
  connect(frame_a, body.frame_a);
  connect(frame_a, toSteerAxis.frame_a);
  connect(toSteerAxis.frame_b, frame_b);
  annotation(Documentation(info = "<html><p>The rear frame B of Meijaard et al. (2007) with the rider
rigidly attached: a rigid body whose centre of mass is at <code>(xB, zB)</code> from the rear contact
point (nominal configuration), and the point where the steer axis meets the ground, at
<code>(w + c, 0)</code>. The frame's origin is the rear axle, at the height <code>rR</code>.</p></html>"));
end RearFrame;
