within Bicycle.Mechanics.Parts;
model RigidBody "Rigid body fixed to frame_a: mass, centre of mass, inertia tensor; gravity along the ground z axis"
  extends Bicycle.Icons.RigidBodyIcon;
  constant Integer n = 6 "Number of generalized speeds";
  parameter Bicycle.Units.Mass m "Mass";
  parameter Bicycle.Units.Position rx = 0 "Centre of mass: x coordinate in frame_a axes";
  parameter Bicycle.Units.Position ry = 0 "Centre of mass: y coordinate in frame_a axes";
  parameter Bicycle.Units.Position rz = 0 "Centre of mass: z coordinate in frame_a axes";
  parameter Bicycle.Units.MomentOfInertia Ixx "Inertia-tensor element Ixx about the centre of mass, frame_a axes";
  parameter Bicycle.Units.MomentOfInertia Iyy "Inertia-tensor element Iyy about the centre of mass, frame_a axes";
  parameter Bicycle.Units.MomentOfInertia Izz "Inertia-tensor element Izz about the centre of mass, frame_a axes";
  parameter Bicycle.Units.MomentOfInertia Ixy = 0 "Inertia-tensor element Ixy about the centre of mass, frame_a axes";
  parameter Bicycle.Units.MomentOfInertia Ixz = 0 "Inertia-tensor element Ixz about the centre of mass, frame_a axes";
  parameter Bicycle.Units.MomentOfInertia Iyz = 0 "Inertia-tensor element Iyz about the centre of mass, frame_a axes";
  Bicycle.Mechanics.Interfaces.Frame_a frame_a(n = n) "Frame the body is fixed to"
    annotation(Placement(transformation(extent = {{-116, -16}, {-84, 16}})));
  Real r_cm[3] "Position of the centre of mass (ground axes) (m)";
protected
  Real rho[3] "Vector from frame_a to the centre of mass (ground axes) (m)";
  Real Vc[3, n] "Partial velocities of the centre of mass (m)";
  Real ac0[3] "Acceleration remainder of the centre of mass (m/s2)";
  Real ac[3] "Acceleration of the centre of mass: Vc*du + ac0 (m/s2)";
  Real al[3] "Angular acceleration: Wp*du + al0 (rad/s2)";
  Real vc[3] "Velocity of the centre of mass: Vc*u (m/s)";
  Real wr[3] "w x rho (m/s)";
  Real Ib[3, 3] "Inertia tensor in frame_a axes (kg.m2)";
  Real IN[3, 3] "Inertia tensor in ground axes: R*Ib*R' (kg.m2)";
  Real H[3] "Angular momentum about the centre of mass (kg.m2/s)";
  Real Ia[3] "IN*al (N.m)";
  Real F[3] "Gravity minus m*ac (N)";
  Real T[3] "-IN*al - w x H (N.m)";
equation
  for i in 1:3 loop
    rho[i] = frame_a.R[i, 1]*rx + frame_a.R[i, 2]*ry + frame_a.R[i, 3]*rz;
  end for;
  r_cm = frame_a.r + rho;
  for j in 1:n loop
    Vc[1, j] = frame_a.Vp[1, j] + frame_a.Wp[2, j]*rho[3] - frame_a.Wp[3, j]*rho[2];
    Vc[2, j] = frame_a.Vp[2, j] + frame_a.Wp[3, j]*rho[1] - frame_a.Wp[1, j]*rho[3];
    Vc[3, j] = frame_a.Vp[3, j] + frame_a.Wp[1, j]*rho[2] - frame_a.Wp[2, j]*rho[1];
  end for;
  wr[1] = frame_a.w[2]*rho[3] - frame_a.w[3]*rho[2];
  wr[2] = frame_a.w[3]*rho[1] - frame_a.w[1]*rho[3];
  wr[3] = frame_a.w[1]*rho[2] - frame_a.w[2]*rho[1];
  ac0[1] = frame_a.a0[1] + frame_a.al0[2]*rho[3] - frame_a.al0[3]*rho[2] + frame_a.w[2]*wr[3] - frame_a.w[3]*wr[2];
  ac0[2] = frame_a.a0[2] + frame_a.al0[3]*rho[1] - frame_a.al0[1]*rho[3] + frame_a.w[3]*wr[1] - frame_a.w[1]*wr[3];
  ac0[3] = frame_a.a0[3] + frame_a.al0[1]*rho[2] - frame_a.al0[2]*rho[1] + frame_a.w[1]*wr[2] - frame_a.w[2]*wr[1];
  Ib[1, 1] = Ixx;
  Ib[1, 2] = Ixy;
  Ib[1, 3] = Ixz;
  Ib[2, 1] = Ixy;
  Ib[2, 2] = Iyy;
  Ib[2, 3] = Iyz;
  Ib[3, 1] = Ixz;
  Ib[3, 2] = Iyz;
  Ib[3, 3] = Izz;
  IN = frame_a.R*Ib*transpose(frame_a.R);
  ac = Vc*frame_a.du + ac0;
  al = frame_a.Wp*frame_a.du + frame_a.al0;
  vc = Vc*frame_a.u;
  H = IN*frame_a.w;
  Ia = IN*al;
  F[1] = -m*ac[1];
  F[2] = -m*ac[2];
  F[3] = m*(frame_a.g - ac[3]);
  T[1] = -Ia[1] - (frame_a.w[2]*H[3] - frame_a.w[3]*H[2]);
  T[2] = -Ia[2] - (frame_a.w[3]*H[1] - frame_a.w[1]*H[3]);
  T[3] = -Ia[3] - (frame_a.w[1]*H[2] - frame_a.w[2]*H[1]);
  // Kane's generalized active and inertia forces of the body; a leaf of the tree owns no speed
  frame_a.F = transpose(Vc)*F + transpose(frame_a.Wp)*T;
  frame_a.us = zeros(n);
  frame_a.E = 0.5*m*(vc[1]^2 + vc[2]^2 + vc[3]^2) + 0.5*(frame_a.w[1]*H[1] + frame_a.w[2]*H[2] + frame_a.w[3]*H[3]) - m*frame_a.g*r_cm[3];
  annotation(Documentation(info = "<html><p>A rigid body with mass <code>m</code>, centre of mass
<code>(rx, ry, rz)</code> and inertia tensor about the centre of mass, all in <code>frame_a</code>
axes. It adds to the connection set of <code>frame_a</code> its generalized active and inertia forces
(Kane's <code>F_r + F_r*</code>) <code>Vc'(m g e_z - m ac) + Wp'(-I al - w x I w)</code>, with the
accelerations written in the generalized accelerations <code>du</code>:
<code>ac = Vc*du + ac0</code>, <code>al = Wp*du + al0</code> (<code>Vc</code>: partial velocities of the
centre of mass, <code>I</code>: the inertia tensor in ground axes). Its mechanical energy is
<code>m |vc|^2/2 + w'I w/2 - m g z</code> (zero at the ground; z points down); gravity
<code>g</code> comes from the ground through the connector.</p></html>"));
end RigidBody;
