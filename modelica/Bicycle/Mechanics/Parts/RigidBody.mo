within Bicycle.Mechanics.Parts;
model RigidBody "Rigid body fixed to frame_a: mass, centre of mass, inertia tensor; gravity along the ground z axis"
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
  parameter Bicycle.Units.Acceleration g = 9.81 "Gravitational acceleration (along the ground z axis, which points down)";
  Bicycle.Mechanics.Interfaces.Frame frame_a(n = n) "Frame the body is fixed to";
  Real r_cm[3] "Position of the centre of mass (ground axes) (m)";
protected
  Real rho[3] "Vector from frame_a to the centre of mass (ground axes) (m)";
  Real Vc[3, n] "Partial velocities of the centre of mass (m)";
  Real ac0[3] "Acceleration remainder of the centre of mass (m/s2)";
  Real wr[3] "w x rho (m/s)";
  Real Ib[3, 3] "Inertia tensor in frame_a axes (kg.m2)";
  Real IN[3, 3] "Inertia tensor in ground axes: R*Ib*R' (kg.m2)";
  Real IW[3, n] "IN*Wp (kg.m2)";
  Real H[3] "Angular momentum about the centre of mass (kg.m2/s)";
  Real Ia[3] "IN*al0 (N.m)";
  Real F[3] "Gravity minus m*ac0 (N)";
  Real T[3] "-IN*al0 - w x H (N.m)";
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
  IW = IN*frame_a.Wp;
  H = IN*frame_a.w;
  Ia = IN*frame_a.al0;
  F[1] = -m*ac0[1];
  F[2] = -m*ac0[2];
  F[3] = m*(g - ac0[3]);
  T[1] = -Ia[1] - (frame_a.w[2]*H[3] - frame_a.w[3]*H[2]);
  T[2] = -Ia[2] - (frame_a.w[3]*H[1] - frame_a.w[1]*H[3]);
  T[3] = -Ia[3] - (frame_a.w[1]*H[2] - frame_a.w[2]*H[1]);
  frame_a.M = m*transpose(Vc)*Vc + transpose(frame_a.Wp)*IW;
  frame_a.f = transpose(Vc)*F + transpose(frame_a.Wp)*T;
  frame_a.Ep = -m*g*r_cm[3];
  annotation(Documentation(info = "<html><p>A rigid body with mass <code>m</code>, centre of mass
<code>{rx, ry, rz}</code> and inertia tensor about the centre of mass, both in frame_a axes. Its
contributions to Kane's equations: generalized mass matrix <code>m Vc'Vc + Wp' I Wp</code> and
generalized forces <code>Vc'(m g e_z - m ac0) + Wp'(-I al0 - w x I w)</code> (<code>Vc</code>,
<code>ac0</code>: partial velocities and acceleration remainder of the centre of mass; <code>I</code>
in ground axes). The potential energy <code>-m g z</code> is zero at the ground (z points down).</p></html>"));
end RigidBody;
