within Bicycle.Mechanics.Frames;
model RearFrame "Rear frame (rider rigidly attached): body, rear axle, steer-head location"
  extends Bicycle.Icons.RearFrameIcon;
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
  Bicycle.Mechanics.Interfaces.Frame_a frame_a(n = n) "Rear axle: origin at the rear wheel centre, x forward, y along the axle (right), z down in the frame's plane"
    annotation(Placement(transformation(extent = {{-116, -16}, {-84, 16}})));
  Bicycle.Mechanics.Interfaces.Frame_b frame_b(n = n) "Steer-head location: the point of the steer axis on the ground of the nominal configuration, axes as frame_a"
    annotation(Placement(transformation(extent = {{84, -16}, {116, 16}})));
  Bicycle.Mechanics.Parts.RigidBody body(n = n, m = mB, rx = xB, rz = zB + rR, Ixx = IBxx, Iyy = IByy, Izz = IBzz, Ixz = IBxz) "Rear frame body with the rider"
    annotation(Placement(transformation(extent = {{-20, 30}, {20, 70}})));
  Bicycle.Mechanics.Parts.FixedTranslation toSteerAxis(n = n, rx = w + c, rz = rR) "Rear axle to the steer axis"
    annotation(Placement(transformation(extent = {{-20, -20}, {20, 20}})));
equation
  connect(frame_a, body.frame_a) annotation(Line(points = {{-100, 0}, {-60, 0}, {-60, 50}, {-20, 50}}, color = {95, 95, 95}, thickness = 0.5));
  connect(frame_a, toSteerAxis.frame_a) annotation(Line(points = {{-100, 0}, {-20, 0}}, color = {95, 95, 95}, thickness = 0.5));
  connect(toSteerAxis.frame_b, frame_b) annotation(Line(points = {{20, 0}, {100, 0}}, color = {95, 95, 95}, thickness = 0.5));
  annotation(
    Icon(graphics = {
      Line(points = {{-100, 0}, {-84, 0}}, color = {95, 95, 95}, thickness = 0.5),
      Line(points = {{76, 18}, {76, 0}, {100, 0}}, color = {95, 95, 95}, thickness = 0.5)}),
    Documentation(info = "<html><p>The rear frame B of Meijaard et al. (2007) with the rider
rigidly attached: a rigid body whose centre of mass is at <code>(xB, zB)</code> from the rear contact
point (nominal configuration), and the point where the steer axis meets the ground, at
<code>(w + c, 0)</code>. The frame's origin is the rear axle, at the height <code>rR</code>.</p></html>"));
end RearFrame;
