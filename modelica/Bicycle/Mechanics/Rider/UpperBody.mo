within Bicycle.Mechanics.Rider;
model UpperBody "Rider's upper body: rigid body whose centre of mass lies the distance l above the hip hinge axis"
  extends Bicycle.Icons.UpperBodyIcon;
  constant Integer n = 7 "Number of generalized speeds of the system";
  parameter Bicycle.Units.Mass m "Mass of the upper body";
  parameter Bicycle.Units.Length l "Height of the centre of mass above the hinge axis (along -z of frame_a)";
  parameter Bicycle.Units.MomentOfInertia Ixx "Inertia-tensor element Ixx about the centre of mass";
  parameter Bicycle.Units.MomentOfInertia Ixz = 0 "Inertia-tensor element Ixz about the centre of mass";
  parameter Bicycle.Units.MomentOfInertia Iyy "Inertia-tensor element Iyy about the centre of mass";
  parameter Bicycle.Units.MomentOfInertia Izz "Inertia-tensor element Izz about the centre of mass";
  Bicycle.Mechanics.Interfaces.Frame_a frame_a(n = n) "Hinge point on the hinge axis; axes of the upper body (parallel to the rear frame's when upright)"
    annotation(Placement(transformation(origin = {0, -100}, extent = {{-16, -16}, {16, 16}}, rotation = 90)));
  Bicycle.Mechanics.Parts.RigidBody body(n = n, m = m, rz = -l, Ixx = Ixx, Iyy = Iyy, Izz = Izz, Ixz = Ixz) "Upper body (trunk, arms, head)"
    annotation(Placement(transformation(origin = {0, 20}, extent = {{-20, -20}, {20, 20}}, rotation = 90)));
equation
  connect(frame_a, body.frame_a) annotation(Line(points = {{0, -100}, {0, 0}}, color = {95, 95, 95}, thickness = 0.5));
  annotation(Documentation(info = "<html><p>The upper body U of a rider leaning at the hips: a rigid body
with mass <code>m</code> whose centre of mass is <code>l</code> above the hinge point along the body's
own vertical (<code>-z</code> of <code>frame_a</code>, the z axis points down), with the inertia tensor
about the centre of mass in the body's axes (<code>Ixy = Iyz = 0</code>: the body is symmetric with
respect to its x-z plane). Attach it to the rear frame through a hinge
(<a href=\"modelica://Bicycle.Mechanics.Rider.HipHinge\">HipHinge</a> or
<a href=\"modelica://Bicycle.Mechanics.Rider.LockedHinge\">LockedHinge</a>).</p></html>"));
end UpperBody;
