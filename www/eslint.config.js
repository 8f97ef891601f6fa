// ESLint for the front end: the recommended JavaScript rules plus typescript-eslint's
// recommended rules for the TypeScript sources and tests.
import js from '@eslint/js';
import tseslint from 'typescript-eslint';

export default tseslint.config(
  { ignores: ['dist/**', 'pkg/**', 'node_modules/**'] },
  js.configs.recommended,
  ...tseslint.configs.recommended,
  {
    files: ['tests/**/*.mjs'],
    languageOptions: { globals: { process: 'readonly', console: 'readonly', setTimeout: 'readonly', URL: 'readonly', Buffer: 'readonly', performance: 'readonly', clearTimeout: 'readonly', document: 'readonly', window: 'readonly', DataTransfer: 'readonly', File: 'readonly', PerformanceObserver: 'readonly', atob: 'readonly', MutationObserver: 'readonly', location: 'readonly' } },
  },
);
