within Bicycle.Mechanics.Frames;
model FrontFrame "Front frame (fork and handlebar): body and front axle"
  extends Bicycle.Icons.FrontFrameIcon;
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
  Bicycle.Mechanics.Interfaces.Frame_a frame_a(n = n) "Steer-axis point (on the ground of the nominal configuration); axes parallel to the rear frame's at zero steer"
    annotation(Placement(transformation(extent = {{-116, -16}, {-84, 16}})));
  Bicycle.Mechanics.Interfaces.Frame_b frame_b(n = n) "Front axle: origin at the front wheel centre, y along the axle"
    annotation(Placement(transformation(origin = {0, -100}, extent = {{-16, -16}, {16, 16}}, rotation = 90)));
  Bicycle.Mechanics.Parts.RigidBody body(n = n, m = mH, rx = xH - w - c, rz = zH, Ixx = IHxx, Iyy = IHyy, Izz = IHzz, Ixz = IHxz) "Fork and handlebar"
    annotation(Placement(transformation(extent = {{-20, 30}, {20, 70}})));
  Bicycle.Mechanics.Parts.FixedTranslation toAxle(n = n, rx = -c, rz = -rF) "Steer-axis point to the front axle"
    annotation(Placement(transformation(extent = {{-20, -60}, {20, -20}})));
equation
  connect(frame_a, body.frame_a) annotation(Line(points = {{-100, 0}, {-60, 0}, {-60, 50}, {-20, 50}}, color = {95, 95, 95}, thickness = 0.5));
  connect(frame_a, toAxle.frame_a) annotation(Line(points = {{-100, 0}, {-60, 0}, {-60, -40}, {-20, -40}}, color = {95, 95, 95}, thickness = 0.5));
  connect(toAxle.frame_b, frame_b) annotation(Line(points = {{20, -40}, {40, -40}, {40, -80}, {0, -80}, {0, -100}}, color = {95, 95, 95}, thickness = 0.5));
  annotation(
    Icon(graphics = {
      Line(points = {{-100, 0}, {-24, 0}}, color = {95, 95, 95}, thickness = 0.5),
      Line(points = {{0, -90}, {0, -100}}, color = {95, 95, 95}, thickness = 0.5)}),
    Documentation(info = "<html><p>The front frame H of Meijaard et al. (2007): a rigid body
with the centre of mass at <code>(xH, zH)</code> from the rear contact point (nominal configuration)
and the front axle at <code>(w, -rF)</code>. Its frame is the steer-axis point with axes parallel
to the rear frame's at zero steer (Meijaard's inertia axes).</p></html>"));
end FrontFrame;
