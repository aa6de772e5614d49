within Bicycle.Mechanics.Joints;
partial model PartialRevolute "Revolute joint that owns its coordinate: frame_b turns relative to frame_a about a body-fixed axis; the angle and its rate are states of the joint"
  extends Bicycle.Icons.RevoluteIcon;
  constant Integer n = 6 "Number of generalized speeds of the system";
  constant Integer k = 1 "Column of the joint's speed among the generalized speeds";
  parameter Real nx(final unit = "1") = 0 "Axis (unit vector): x component in frame_a axes";
  parameter Real ny(final unit = "1") = 1 "Axis (unit vector): y component in frame_a axes";
  parameter Real nz(final unit = "1") = 0 "Axis (unit vector): z component in frame_a axes";
  parameter Bicycle.Units.Angle angle0 = 0 "Initial angle";
  parameter Bicycle.Units.AngularVelocity omega0 = 0 "Initial rate";
  Bicycle.Mechanics.Interfaces.Frame_a frame_a(n = n) "Frame the joint is fixed to"
    annotation(Placement(transformation(extent = {{-116, -16}, {-84, 16}})));
  Bicycle.Mechanics.Interfaces.Frame_b frame_b(n = n) "Frame that turns about the axis"
    annotation(Placement(transformation(extent = {{84, -16}, {116, 16}})));
  Bicycle.Units.Angle angle(start = angle0, fixed = true) "Rotation angle of frame_b relative to frame_a about the axis";
  Bicycle.Units.AngularVelocity omega(start = omega0, fixed = true) "Rotation rate der(angle): the generalized speed k";
  Bicycle.Units.Torque tau "Torque on frame_b about the axis (and -tau on frame_a): the generalized force of the coordinate";
  Bicycle.Units.Energy Ej "Energy stored in the joint (a spring's)";
  Bicycle.Units.Torque Fa "Generalized force of the joint's coordinate at frame_a: tau plus that of the bodies beyond (a held joint: its own equation of motion)";
protected
  Real e[3] "Axis in ground axes";
  Real Rrel[3, 3] "Orientation of frame_b relative to frame_a (Rodrigues' formula)";
  Real we[3] "w x e (1/s)";
equation
  der(angle) = omega;
  der(omega) = frame_a.du[k];
  for i in 1:3 loop
    e[i] = frame_a.R[i, 1]*nx + frame_a.R[i, 2]*ny + frame_a.R[i, 3]*nz;
  end for;
  Rrel[1, 1] = cos(angle) + (1 - cos(angle))*nx*nx;
  Rrel[1, 2] = (1 - cos(angle))*nx*ny - sin(angle)*nz;
  Rrel[1, 3] = (1 - cos(angle))*nx*nz + sin(angle)*ny;
  Rrel[2, 1] = (1 - cos(angle))*ny*nx + sin(angle)*nz;
  Rrel[2, 2] = cos(angle) + (1 - cos(angle))*ny*ny;
  Rrel[2, 3] = (1 - cos(angle))*ny*nz - sin(angle)*nx;
  Rrel[3, 1] = (1 - cos(angle))*nz*nx - sin(angle)*ny;
  Rrel[3, 2] = (1 - cos(angle))*nz*ny + sin(angle)*nx;
  Rrel[3, 3] = cos(angle) + (1 - cos(angle))*nz*nz;
  frame_b.R = frame_a.R*Rrel;
  frame_b.r = frame_a.r;
  frame_b.Vp = frame_a.Vp;
  frame_b.a0 = frame_a.a0;
  frame_b.w = frame_a.w + e*omega;
  for j in 1:n loop
    frame_b.Wp[1, j] = frame_a.Wp[1, j] + (if j == k then e[1] else 0);
    frame_b.Wp[2, j] = frame_a.Wp[2, j] + (if j == k then e[2] else 0);
    frame_b.Wp[3, j] = frame_a.Wp[3, j] + (if j == k then e[3] else 0);
  end for;
  we[1] = frame_a.w[2]*e[3] - frame_a.w[3]*e[2];
  we[2] = frame_a.w[3]*e[1] - frame_a.w[1]*e[3];
  we[3] = frame_a.w[1]*e[2] - frame_a.w[2]*e[1];
  frame_b.al0 = frame_a.al0 + we*omega;
  // Massless: the pairs pass through; the joint adds its own speed (column k), and the extending
  // class says what the generalized force of its coordinate is (Fa)
  frame_b.u = frame_a.u;
  for j in 1:n loop
    frame_a.us[j] + frame_b.us[j] = if j == k then omega else 0;
    frame_a.F[j] = if j == k then Fa else -frame_b.F[j];
  end for;
  frame_b.du = frame_a.du;
  frame_b.g = frame_a.g;
  frame_a.E + frame_b.E = Ej;
  annotation(Documentation(info = "<html><p>frame_b is frame_a turned by the joint's angle
<code>angle</code> about the unit axis <code>{nx, ny, nz}</code> (frame_a axes). The joint owns its
coordinate: the angle and its rate <code>omega</code> are its states, <code>omega</code> is the
generalized speed in column <code>k</code> (it adds it to the flow <code>us</code>, from which the
ground reads every joint's speed), and its acceleration is the generalized acceleration
<code>du[k]</code> that Kane's equations give. Column <code>k</code> of the partial angular
velocities gains the axis <code>e</code> (ground axes), the angular velocity gains
<code>e*omega</code> and the angular acceleration remainder <code>(w x e)*omega</code>. The torque
<code>tau</code> (on frame_b, reaction on frame_a) is the generalized force of the coordinate; the
extending classes say what it is.</p></html>"));
end PartialRevolute;
