% Peter Corke's SerialLink, as documented: SerialLink(L, 'name', NAME, 'base', B, 'tool', T);
% fkine(q) = base * A_1(q_1) * ... * A_n(q_n) * tool (a 4x4 matrix here). Written for
% urdf2dh's tests from the documentation and the book, no code of the toolbox.
classdef SerialLink
  properties
    links; name = ''; base = eye(4); tool = eye(4);
  end
  methods
    function r = SerialLink(L, varargin)
      r.links = L;
      for i = 1:2:numel(varargin)
        switch varargin{i}
          case 'name', r.name = varargin{i + 1};
          case 'base', r.base = varargin{i + 1};
          case 'tool', r.tool = varargin{i + 1};
          otherwise, error('SerialLink: option %s not understood', varargin{i});
        end
      end
    end
    function T = fkine(r, q)
      T = r.base;
      for i = 1:numel(r.links)
        T = T * r.links(i).A(q(i));
      end
      T = T * r.tool;
    end
  end
end
