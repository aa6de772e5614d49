within Bicycle.Mechanics.Parts;
model FixedTranslation "Rigid translation from frame_a to frame_b (same orientation)"
  extends Bicycle.Icons.FixedTranslationIcon;
  constant Integer n = 6 "Number of generalized speeds";
  parameter Bicycle.Units.Position rx = 0 "Vector from frame_a to frame_b: x component in frame_a axes";
  parameter Bicycle.Units.Position ry = 0 "Vector from frame_a to frame_b: y component in frame_a axes";
  parameter Bicycle.Units.Position rz = 0 "Vector from frame_a to frame_b: z component in frame_a axes";
  Bicycle.Mechanics.Interfaces.Frame_a frame_a(n = n) "Frame at the start of the translation"
    annotation(Placement(transformation(extent = {{-116, -16}, {-84, 16}})));
  Bicycle.Mechanics.Interfaces.Frame_b frame_b(n = n) "Frame at the end of the translation"
    annotation(Placement(transformation(extent = {{84, -16}, {116, 16}})));
protected
  Real rho[3] "Vector from frame_a to frame_b (ground axes) (m)";
  Real wr[3] "w x rho (m/s)";
equation
  for i in 1:3 loop
    rho[i] = frame_a.R[i, 1]*rx + frame_a.R[i, 2]*ry + frame_a.R[i, 3]*rz;
  end for;
  frame_b.R = frame_a.R;
  frame_b.r = frame_a.r + rho;
  frame_b.w = frame_a.w;
  frame_b.Wp = frame_a.Wp;
  frame_b.al0 = frame_a.al0;
  // Vp_b = Vp_a + Wp x rho (column by column)
  for j in 1:n loop
    frame_b.Vp[1, j] = frame_a.Vp[1, j] + frame_a.Wp[2, j]*rho[3] - frame_a.Wp[3, j]*rho[2];
    frame_b.Vp[2, j] = frame_a.Vp[2, j] + frame_a.Wp[3, j]*rho[1] - frame_a.Wp[1, j]*rho[3];
    frame_b.Vp[3, j] = frame_a.Vp[3, j] + frame_a.Wp[1, j]*rho[2] - frame_a.Wp[2, j]*rho[1];
  end for;
  // a0_b = a0_a + al0 x rho + w x (w x rho)
  wr[1] = frame_a.w[2]*rho[3] - frame_a.w[3]*rho[2];
  wr[2] = frame_a.w[3]*rho[1] - frame_a.w[1]*rho[3];
  wr[3] = frame_a.w[1]*rho[2] - frame_a.w[2]*rho[1];
  frame_b.a0[1] = frame_a.a0[1] + frame_a.al0[2]*rho[3] - frame_a.al0[3]*rho[2] + frame_a.w[2]*wr[3] - frame_a.w[3]*wr[2];
  frame_b.a0[2] = frame_a.a0[2] + frame_a.al0[3]*rho[1] - frame_a.al0[1]*rho[3] + frame_a.w[3]*wr[1] - frame_a.w[1]*wr[3];
  frame_b.a0[3] = frame_a.a0[3] + frame_a.al0[1]*rho[2] - frame_a.al0[2]*rho[1] + frame_a.w[1]*wr[2] - frame_a.w[2]*wr[1];
  // Massless and without a coordinate: the pairs pass through
  frame_b.u = frame_a.u;
  zeros(n) = frame_a.us + frame_b.us;
  frame_b.du = frame_a.du;
  zeros(n) = frame_a.F + frame_b.F;
  frame_b.g = frame_a.g;
  0 = frame_a.E + frame_b.E;
  annotation(Documentation(info = "<html><p>frame_b is frame_a shifted by the body-fixed vector
<code>{rx, ry, rz}</code> (frame_a axes). Its partial velocities are <code>Vp + Wp x rho</code> and its
acceleration remainder <code>a0 + al0 x rho + w x (w x rho)</code>, with <code>rho</code> the vector in
ground axes.</p></html>"));
end FixedTranslation;
