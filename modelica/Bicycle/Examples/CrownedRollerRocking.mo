within Bicycle.Examples;
model CrownedRollerRocking "Bicycle on crowned rollers with R > h: undamped rocking from an initial lean, eq (27)"
  extends Bicycle.Icons.Example;
  Bicycle.Bicycles.CrownedRoller bicycle(R = 1.2, V = 2, delta = 0, frame(phi(start = 0.05))) "Rocking radius 1.2 m > h = 1 m, steer angle held at zero"
    annotation(Placement(transformation(extent = {{-40, -40}, {40, 40}})));
  annotation(
    experiment(StartTime = 0, StopTime = 10, Tolerance = 1e-8, Interval = 0.01),
    Documentation(info = "<html>
<p>With R &gt; h gravity rights the bicycle: the poles (27) are imaginary,
+-j*sqrt(m*g*(R - h)/J) = +-1.37j rad/s for the Table 1 bicycle with R = 1.2 m, and the initial lean
of 0.05 rad oscillates with a period of 4.6 s without damping (nothing in the model dissipates
energy). With R &lt; h the same lean grows like exp(sqrt(m*g*(h - R)/J)*t).</p>
</html>"));
end CrownedRollerRocking;
